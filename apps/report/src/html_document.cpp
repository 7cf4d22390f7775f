#include "imuconv/report/html_document.h"

#include <algorithm>

#include "imuconv/report/markup.h"

namespace imuconv::report {
namespace {

// Everything is inline; 'unsafe-inline' admits only the <style> element below (there is no
// script to admit), and default-src 'none' refuses every fetch: images, fonts, frames, links.
constexpr const char* kPolicy = "default-src 'none'; style-src 'unsafe-inline'";

constexpr const char* kStyle =
    "body{font-family:sans-serif;margin:1.5em auto;max-width:1200px;padding:0 1em;color:#222}"
    "h1{font-size:1.5em}h2{font-size:1.25em;margin-top:1.6em;border-bottom:1px solid "
    "#ccc}h3{font-size:1.05em}"
    "table{border-collapse:collapse;margin:0.8em 0;font-size:0.9em}"
    "th,td{border:1px solid #ccc;padding:0.25em 0.6em;text-align:left;vertical-align:top}"
    "th{background:#f3f3f3}"
    "code{font-family:monospace;background:#f6f6f6;padding:0.1em 0.3em;overflow-wrap:anywhere}"
    ".figures{display:flex;flex-wrap:wrap;gap:1.2em;align-items:flex-start}"
    // A figure as a table whose caption row wraps at the figure's own width.
    "figure{margin:0.5em 0;display:table}"
    "figcaption{display:table-caption;caption-side:bottom;font-size:0.85em;color:#444}"
    // The verdict badge: green for consistent, dark red for inconsistent, white bold text (both
    // above 4.5:1 contrast), so the judgment reads before anything else on the page.
    ".verdict{display:inline-block;padding:0.45em "
    "0.9em;border-radius:0.4em;color:#fff;margin:0.2em 0 0.8em}"
    ".verdict[data-verdict=consistent]{background:#1b7a35}.verdict[data-verdict=inconsistent]{"
    "background:#a50f15}"
    ".verdict-word{font-weight:bold;font-size:1.15em;text-transform:uppercase;margin-right:0.6em}";

}  // namespace

HtmlDocument::HtmlDocument(std::string title) : title_(std::move(title)) {}

void HtmlDocument::AddHeading(int level, std::string_view text) {
  const std::string h = "h" + std::to_string(std::clamp(level, 1, 6));
  body_ += "<" + h + ">" + EscapeText(text) + "</" + h + ">\n";
}

void HtmlDocument::AddParagraph(std::string_view text) {
  body_ += "<p>" + EscapeText(text) + "</p>\n";
}

void HtmlDocument::AddVerdict(bool consistent, std::string_view reason) {
  const char* word = consistent ? "consistent" : "inconsistent";
  body_ += std::string("<div class=\"verdict\" data-verdict=\"") + word +
           "\"><span class=\"verdict-word\">" + word + "</span><span class=\"verdict-reason\">" +
           EscapeText(reason) + "</span></div>\n";
}

void HtmlDocument::AddCode(std::string_view text) {
  body_ += "<p><code>" + EscapeText(text) + "</code></p>\n";
}

void HtmlDocument::AddList(const std::vector<std::string>& items) {
  body_ += "<ul>\n";
  for (const auto& i : items) body_ += "<li>" + EscapeText(i) + "</li>\n";
  body_ += "</ul>\n";
}

void HtmlDocument::AddTable(const std::vector<std::string>& header,
                            const std::vector<std::vector<std::string>>& rows) {
  std::size_t width = header.size();
  for (const auto& r : rows) width = std::max(width, r.size());
  body_ += "<table>\n<thead><tr>";
  for (std::size_t k = 0; k < width; ++k)
    body_ += "<th>" + (k < header.size() ? EscapeText(header[k]) : "") + "</th>";
  body_ += "</tr></thead>\n<tbody>\n";
  for (const auto& r : rows) {
    body_ += "<tr>";
    for (std::size_t k = 0; k < width; ++k)
      body_ += "<td>" + (k < r.size() ? EscapeText(r[k]) : "") + "</td>";
    body_ += "</tr>\n";
  }
  body_ += "</tbody>\n</table>\n";
}

void HtmlDocument::AddFigures(const std::vector<Figure>& figures) {
  body_ += "<div class=\"figures\">\n";
  for (const auto& f : figures)
    body_ += "<figure>\n" + f.svg + "<figcaption>" + EscapeText(f.caption) +
             "</figcaption>\n</figure>\n";
  body_ += "</div>\n";
}

std::string HtmlDocument::Render() const {
  return std::string(
             "<!DOCTYPE html>\n<html xmlns=\"http://www.w3.org/1999/xhtml\" "
             "lang=\"en\">\n<head>\n") +
         "<meta charset=\"utf-8\"/>\n<meta http-equiv=\"Content-Security-Policy\" content=\"" +
         kPolicy + "\"/>\n" +
         "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\"/>\n<title>" +
         EscapeText(title_) + "</title>\n<style>" + kStyle + "</style>\n</head>\n<body>\n<h1>" +
         EscapeText(title_) + "</h1>\n" + body_ + "</body>\n</html>\n";
}

}  // namespace imuconv::report
