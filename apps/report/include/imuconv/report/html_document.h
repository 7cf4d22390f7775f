// One self-contained HTML report: inline CSS, inline SVG figures, no script, no font, no image
// file, nothing fetched. A Content-Security-Policy in the document forbids every load, so a
// browser refuses (and reports) anything that would reach out, should a figure ever hold a link.
// The document is also well-formed XML (XHTML syntax), which the tests parse.
//
// Text arguments are text: escaped here (markup.h). Figure markup must come from HeatmapSvg or
// ChartSvg, which escape their own labels; never pass text from outside as markup.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace imuconv::report {

class HtmlDocument {
 public:
  explicit HtmlDocument(std::string title);

  /// <h1>..<h6> (level clamped to 1..6). The title is already the page's <h1>.
  void AddHeading(int level, std::string_view text);
  void AddParagraph(std::string_view text);
  /// The judgment as a coloured badge, <div class="verdict"
  /// data-verdict="consistent|inconsistent">: the word and the one-line reason. Call it first, so
  /// it is at the top under the title.
  void AddVerdict(bool consistent, std::string_view reason);
  /// Text in a fixed-width font (a command line, a path).
  void AddCode(std::string_view text);
  void AddList(const std::vector<std::string>& items);
  /// A table: a header row, then rows (a short row is padded with empty cells).
  void AddTable(const std::vector<std::string>& header,
                const std::vector<std::vector<std::string>>& rows);
  /// Figures side by side (wrapping on a narrow window), each an SVG element and its caption.
  struct Figure {
    std::string svg;  ///< markup from HeatmapSvg or ChartSvg
    std::string caption;
  };
  void AddFigures(const std::vector<Figure>& figures);

  /// The whole document.
  std::string Render() const;

 private:
  std::string title_;
  std::string body_;
};

}  // namespace imuconv::report
