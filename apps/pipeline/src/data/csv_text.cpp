#include "csv_text.h"

#include <charconv>

#include "imuconv/printable.h"

namespace imuconv::pipeline::data {

std::string_view Trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r'))
    s.remove_suffix(1);
  return s;
}

bool IsBlank(std::string_view s) { return Trim(s).empty(); }

std::optional<double> ParseDouble(std::string_view s) {
  s = Trim(s);
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  if (s.empty()) return std::nullopt;
  double v = 0.0;
  const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
  if (r.ec != std::errc() || r.ptr != s.data() + s.size()) return std::nullopt;
  return v;
}

void Split(std::string_view line, char delim, bool whitespace, std::vector<std::string_view>& out) {
  out.clear();
  if (whitespace) {
    std::size_t i = 0;
    while (i < line.size()) {
      while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
      if (i >= line.size()) break;
      std::size_t j = i;
      while (j < line.size() && line[j] != ' ' && line[j] != '\t') ++j;
      out.push_back(line.substr(i, j - i));
      i = j;
    }
    return;
  }
  std::size_t start = 0;
  while (true) {
    const std::size_t pos = line.find(delim, start);
    if (pos == std::string_view::npos) {
      out.push_back(Trim(line.substr(start)));
      return;
    }
    out.push_back(Trim(line.substr(start, pos - start)));
    start = pos + 1;
  }
}

std::string ShownBare(std::string_view s) {
  // 40 bytes: enough to recognise a number or a word, short enough for one line.
  std::string t = Printable(s.substr(0, 40));
  if (s.size() > 40) t += "...";
  return t;
}

std::string Shown(std::string_view s) { return "'" + ShownBare(s) + "'"; }

std::string DelimiterName(char d, bool ws) {
  if (ws) return "whitespace";
  if (d == '\t') return "tab";
  return Quoted(std::string_view(&d, 1));
}

}  // namespace imuconv::pipeline::data
