// The few SVG elements the heatmap and the charts are drawn with, as strings: every number
// through Coordinate, every text through EscapeText (markup.h). Private to the report library.
#pragma once

#include <string>
#include <string_view>

#include "imuconv/report/markup.h"

namespace imuconv::report::svg {

/// `<svg ...>` opening an element of the given size, with the font every text inherits (a
/// generic family: the report loads no font).
/// `extra`: further attributes, already escaped (e.g. data-* attributes from Coordinate/Readable).
inline std::string Open(double width, double height, std::string_view cls,
                        std::string_view aria_label, std::string_view extra = "") {
  return "<svg xmlns=\"http://www.w3.org/2000/svg\" class=\"" + std::string(cls) + "\"" +
         (extra.empty() ? "" : " ") + std::string(extra) + " width=\"" + Coordinate(width) +
         "\" height=\"" + Coordinate(height) + "\" viewBox=\"0 0 " + Coordinate(width) + " " +
         Coordinate(height) + "\" role=\"img\" aria-label=\"" + EscapeText(aria_label) +
         "\" font-family=\"sans-serif\" font-size=\"11\">\n";
}

inline std::string Rect(double x, double y, double w, double h, std::string_view fill,
                        std::string_view extra = "") {
  return "<rect x=\"" + Coordinate(x) + "\" y=\"" + Coordinate(y) + "\" width=\"" + Coordinate(w) +
         "\" height=\"" + Coordinate(h) + "\" fill=\"" + std::string(fill) + "\"" +
         (extra.empty() ? "" : " ") + std::string(extra) + "/>";
}

inline std::string Line(double x1, double y1, double x2, double y2, std::string_view stroke,
                        double width, std::string_view extra = "") {
  return "<line x1=\"" + Coordinate(x1) + "\" y1=\"" + Coordinate(y1) + "\" x2=\"" +
         Coordinate(x2) + "\" y2=\"" + Coordinate(y2) + "\" stroke=\"" + std::string(stroke) +
         "\" stroke-width=\"" + Coordinate(width) + "\"" + (extra.empty() ? "" : " ") +
         std::string(extra) + "/>";
}

/// anchor: "start", "middle" or "end"; `text` is escaped here.
inline std::string Text(double x, double y, std::string_view text, std::string_view anchor,
                        std::string_view cls, std::string_view extra = "") {
  return "<text class=\"" + std::string(cls) + "\" x=\"" + Coordinate(x) + "\" y=\"" +
         Coordinate(y) + "\" text-anchor=\"" + std::string(anchor) + "\"" +
         (extra.empty() ? "" : " ") + std::string(extra) + ">" + EscapeText(text) + "</text>";
}

}  // namespace imuconv::report::svg
