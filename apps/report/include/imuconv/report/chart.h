// A simple x-y chart as an SVG element: point or line series, filled bands (a ±3 sigma
// envelope), bars (a histogram) and labelled reference lines (chi-square bounds), on linear or
// log axes with ticks. Enough for the reports' figures, nothing more.
//
// What cannot be drawn is said, not dropped in silence: a point that is not finite, or not
// positive on a log axis, is left out and its series' legend entry says how many were. A series
// longer than `max_points` is thinned to the smallest and largest y of each of max_points / 2
// runs of consecutive points (a band: the lowest `lo` and highest `hi`), so every extreme stays
// visible, and its legend entry says so.
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace imuconv::report {

struct ChartAxis {
  std::string label;
  bool log = false;
  std::optional<double> min, max;  ///< fixed ends; by default the data's range (with tick room)
};

struct PointSeries {
  std::string name;
  std::vector<double> x, y;
  std::string color = "#1f77b4";
  bool line = false;    ///< joined by a polyline, else dots
  double radius = 2.0;  ///< of a dot
};

/// The region between lo(x) and hi(x), filled.
struct Band {
  std::string name;
  std::vector<double> x, lo, hi;
  std::string color = "#ff7f0e";
  double opacity = 0.25;
};

/// Bars over [edges[i], edges[i + 1]) of height heights[i] (edges.size() == heights.size() + 1).
struct Bars {
  std::string name;
  std::vector<double> edges, heights;
  std::string color = "#9ecae1";
};

/// A full-width (horizontal, at y) or full-height (vertical, at x) line with its name.
struct ReferenceLine {
  std::string name;
  double at = 0.0;
  bool vertical = false;
  std::string color = "#d62728";
  bool dashed = true;
};

struct ChartSpec {
  std::string title;
  ChartAxis x, y;
  std::vector<Bars> bars;
  std::vector<Band> bands;
  std::vector<PointSeries> series;
  std::vector<ReferenceLine> lines;
  double width = 560.0, height = 280.0;  ///< px, the whole element
  std::size_t max_points = 2000;         ///< per series or band, see the file comment
};

/// The chart as one <svg> element, every text escaped. Throws std::invalid_argument when a
/// series' (band's, bars') arrays differ in length.
std::string ChartSvg(const ChartSpec& spec);

}  // namespace imuconv::report
