#include "imuconv/report/chart.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "imuconv/report/markup.h"
#include "svg_elements.h"

namespace imuconv::report {
namespace {

constexpr double kLegendCharWidth =
    6.5;  // of an 11 px sans-serif character, for the legend's layout
constexpr double kLeft = 64.0, kRight = 24.0, kBottom = 38.0, kPad = 6.0;

struct Range {
  double lo = std::numeric_limits<double>::infinity(),
         hi = -std::numeric_limits<double>::infinity();
  void add(double v) {
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  bool empty() const { return !(lo <= hi); }
};

// One axis once its range is known: value to pixel, and its ticks.
struct Scale {
  bool log = false;
  double lo = 0.0, hi = 1.0;  // in log10 units for a log axis
  double px0 = 0.0, px1 = 1.0;
  std::vector<double> ticks;  // values (not log10)
  double operator()(double v) const {
    const double u = log ? std::log10(v) : v;
    return px0 + (u - lo) / (hi - lo) * (px1 - px0);
  }
};

bool Drawable(double v, bool log) { return std::isfinite(v) && (!log || v > 0.0); }

// A linear axis over [lo, hi] widened to whole steps of 1, 2 or 5 times a power of ten, about
// five of them.
void LinearTicks(Range r, const ChartAxis& a, Scale& s) {
  if (r.empty()) r = {0.0, 1.0};
  if (a.min) r.lo = *a.min;
  if (a.max) r.hi = *a.max;
  if (!(r.hi > r.lo)) {
    const double pad = r.lo != 0.0 ? std::abs(r.lo) * 0.1 : 1.0;
    r = {r.lo - pad, r.hi + pad};
  }
  const double raw = (r.hi - r.lo) / 5.0;
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  double step = mag;
  for (double f : {1.0, 2.0, 5.0, 10.0})
    if (raw <= f * mag * 1.000001) {
      step = f * mag;
      break;
    }
  s.log = false;
  s.lo = a.min ? *a.min : std::floor(r.lo / step) * step;
  s.hi = a.max ? *a.max : std::ceil(r.hi / step) * step;
  for (double k = std::ceil(s.lo / step - 1e-9); k * step <= s.hi + step * 1e-9; k += 1.0)
    s.ticks.push_back(std::abs(k) < 0.5 ? 0.0 : k * step);
}

// A log axis over whole decades.
void LogTicks(Range r, const ChartAxis& a, Scale& s) {
  if (r.empty()) r = {1.0, 10.0};
  if (a.min && *a.min > 0) r.lo = *a.min;
  if (a.max && *a.max > 0) r.hi = *a.max;
  s.log = true;
  s.lo = a.min && *a.min > 0 ? std::log10(*a.min) : std::floor(std::log10(r.lo));
  s.hi = a.max && *a.max > 0 ? std::log10(*a.max) : std::ceil(std::log10(r.hi));
  if (!(s.hi > s.lo)) s.hi = s.lo + 1.0;
  const int first = static_cast<int>(std::ceil(s.lo - 1e-9)),
            last = static_cast<int>(std::floor(s.hi + 1e-9));
  const int step = std::max(1, (last - first + 7) / 8);
  for (int k = first; k <= last; k += step) s.ticks.push_back(std::pow(10.0, k));
}

// The indices kept of n points: all of them, or the smallest and largest `key` of each of
// max_points / 2 consecutive runs, in order.
template <typename Low, typename High>
std::vector<std::size_t> Thin(std::size_t n, std::size_t max_points, Low low, High high) {
  std::vector<std::size_t> keep;
  if (n <= max_points || max_points < 2) {
    for (std::size_t i = 0; i < n; ++i) keep.push_back(i);
    return keep;
  }
  const std::size_t runs = max_points / 2;
  for (std::size_t r = 0; r < runs; ++r) {
    const std::size_t b = n * r / runs, e = n * (r + 1) / runs;
    if (b == e) continue;
    std::size_t imin = b, imax = b;
    for (std::size_t i = b; i < e; ++i) {
      if (low(i) < low(imin)) imin = i;
      if (high(i) > high(imax)) imax = i;
    }
    keep.push_back(std::min(imin, imax));
    if (imin != imax) keep.push_back(std::max(imin, imax));
  }
  return keep;
}

std::string LegendName(const std::string& name, std::size_t skipped, std::size_t total,
                       std::size_t shown, bool thinned) {
  std::string s = name;
  if (skipped) s += " (" + std::to_string(skipped) + " not drawable, left out)";
  if (thinned)
    s += " (" + std::to_string(shown) + " of " + std::to_string(total) + " shown, extremes kept)";
  return s;
}

struct LegendItem {
  std::string text, color;
  enum { dot, line, dashed, fill } kind;
};

}  // namespace

std::string ChartSvg(const ChartSpec& spec) {
  const bool xlog = spec.x.log, ylog = spec.y.log;
  for (const auto& s : spec.series)
    if (s.x.size() != s.y.size())
      throw std::invalid_argument("chart: series '" + s.name + "': x and y differ in length");
  for (const auto& b : spec.bands)
    if (b.x.size() != b.lo.size() || b.x.size() != b.hi.size())
      throw std::invalid_argument("chart: band '" + b.name + "': x, lo and hi differ in length");
  for (const auto& b : spec.bars)
    if (b.edges.size() != b.heights.size() + 1)
      throw std::invalid_argument("chart: bars '" + b.name + "': need one more edge than heights");

  // What is drawn of each series and band, and the data's range.
  Range rx, ry;
  std::vector<LegendItem> legend;
  std::vector<std::vector<std::size_t>> series_keep, band_keep;
  for (const auto& b : spec.bars) {
    for (std::size_t i = 0; i < b.heights.size(); ++i) {
      if (!Drawable(b.edges[i], xlog) || !Drawable(b.edges[i + 1], xlog) ||
          !Drawable(b.heights[i], ylog))
        continue;
      rx.add(b.edges[i]);
      rx.add(b.edges[i + 1]);
      ry.add(b.heights[i]);
    }
    if (!ylog) ry.add(0.0);
    legend.push_back({b.name, b.color, LegendItem::fill});
  }
  for (const auto& b : spec.bands) {
    std::vector<std::size_t> ok;
    for (std::size_t i = 0; i < b.x.size(); ++i)
      if (Drawable(b.x[i], xlog) && Drawable(b.lo[i], ylog) && Drawable(b.hi[i], ylog))
        ok.push_back(i);
    std::vector<std::size_t> keep;
    for (std::size_t k : Thin(
             ok.size(), spec.max_points, [&](std::size_t i) { return b.lo[ok[i]]; },
             [&](std::size_t i) { return b.hi[ok[i]]; }))
      keep.push_back(ok[k]);
    for (std::size_t i : keep) {
      rx.add(b.x[i]);
      ry.add(b.lo[i]);
      ry.add(b.hi[i]);
    }
    legend.push_back({LegendName(b.name, b.x.size() - ok.size(), ok.size(), keep.size(),
                                 keep.size() < ok.size()),
                      b.color, LegendItem::fill});
    band_keep.push_back(std::move(keep));
  }
  for (const auto& s : spec.series) {
    std::vector<std::size_t> ok;
    for (std::size_t i = 0; i < s.x.size(); ++i)
      if (Drawable(s.x[i], xlog) && Drawable(s.y[i], ylog)) ok.push_back(i);
    std::vector<std::size_t> keep;
    const auto y = [&](std::size_t i) { return s.y[ok[i]]; };
    for (std::size_t k : Thin(ok.size(), spec.max_points, y, y)) keep.push_back(ok[k]);
    for (std::size_t i : keep) {
      rx.add(s.x[i]);
      ry.add(s.y[i]);
    }
    legend.push_back({LegendName(s.name, s.x.size() - ok.size(), ok.size(), keep.size(),
                                 keep.size() < ok.size()),
                      s.color, s.line ? LegendItem::line : LegendItem::dot});
    series_keep.push_back(std::move(keep));
  }
  for (const auto& l : spec.lines) {
    if (Drawable(l.at, l.vertical ? xlog : ylog)) (l.vertical ? rx : ry).add(l.at);
    legend.push_back({l.name, l.color, l.dashed ? LegendItem::dashed : LegendItem::line});
  }

  // The legend's rows, wrapped at the chart's width, then the plot area below them.
  const double title_h = spec.title.empty() ? 0.0 : 18.0;
  std::vector<std::vector<std::pair<const LegendItem*, double>>> rows(1);
  double row_w = 0.0;
  for (const auto& item : legend) {
    if (item.text.empty()) continue;
    const double w = 22.0 + kLegendCharWidth * static_cast<double>(item.text.size()) + 12.0;
    if (row_w + w > spec.width - kLeft && !rows.back().empty()) {
      rows.emplace_back();
      row_w = 0.0;
    }
    rows.back().push_back({&item, kLeft + row_w});
    row_w += w;
  }
  if (rows.back().empty()) rows.pop_back();
  const double top = kPad + title_h + 15.0 * static_cast<double>(rows.size()) + 6.0;

  Scale sx, sy;
  (xlog ? LogTicks : LinearTicks)(rx, spec.x, sx);
  (ylog ? LogTicks : LinearTicks)(ry, spec.y, sy);
  const double pw = spec.width - kLeft - kRight, ph = spec.height - top - kBottom;
  if (!(pw > 20.0 && ph > 20.0))
    throw std::invalid_argument("chart: too small for its legend and axes");
  sx.px0 = 0.0;
  sx.px1 = pw;
  sy.px0 = ph;
  sy.px1 = 0.0;

  std::string out =
      svg::Open(spec.width, spec.height, "chart", spec.title.empty() ? "chart" : spec.title);
  if (!spec.title.empty())
    out += svg::Text(kLeft, kPad + 12.0, spec.title, "start", "title", "font-size=\"13\"") + "\n";
  out += "<g class=\"legend\">";
  for (std::size_t r = 0; r < rows.size(); ++r)
    for (const auto& [item, x] : rows[r]) {
      const double y = kPad + title_h + 15.0 * r + 8.0;
      switch (item->kind) {
        case LegendItem::dot:
          out += "<circle cx=\"" + Coordinate(x + 8.0) + "\" cy=\"" + Coordinate(y) +
                 "\" r=\"3\" fill=\"" + EscapeText(item->color) + "\"/>";
          break;
        case LegendItem::fill:
          out += svg::Rect(x, y - 5.0, 16.0, 10.0, EscapeText(item->color), "fill-opacity=\"0.6\"");
          break;
        default:
          out += svg::Line(x, y, x + 16.0, y, EscapeText(item->color), 2.0,
                           item->kind == LegendItem::dashed ? "stroke-dasharray=\"5,3\"" : "");
      }
      out += svg::Text(x + 22.0, y + 4.0, item->text, "start", "legend-label");
    }
  out += "</g>\n";

  // Axes: grid and tick labels in the outer coordinates, the data in a nested <svg> that clips
  // to the plot area (a nested svg clips by default: no clipPath, so no ids to collide when
  // several charts share a page).
  out += "<g class=\"axes\" transform=\"translate(" + Coordinate(kLeft) + "," + Coordinate(top) +
         ")\">\n";
  for (double t : sx.ticks) {
    const double px = sx(t);
    out += svg::Line(px, 0.0, px, ph, "#e6e6e6", 1.0) +
           svg::Text(px, ph + 14.0, Readable(t, 4), "middle", "x-tick") + "\n";
  }
  for (double t : sy.ticks) {
    const double py = sy(t);
    out += svg::Line(0.0, py, pw, py, "#e6e6e6", 1.0) +
           svg::Text(-5.0, py + 4.0, Readable(t, 4), "end", "y-tick") + "\n";
  }
  out += svg::Rect(0.0, 0.0, pw, ph, "none", "stroke=\"#333333\" stroke-width=\"1\"") + "\n";
  out += svg::Text(pw / 2.0, ph + 30.0, spec.x.label, "middle", "x-label") + "\n";
  out += svg::Text(0.0, 0.0, spec.y.label, "middle", "y-label",
                   "transform=\"translate(" + Coordinate(-kLeft + 14.0) + "," +
                       Coordinate(ph / 2.0) + ") rotate(-90)\"") +
         "\n";

  out += "<svg class=\"plot\" x=\"0\" y=\"0\" width=\"" + Coordinate(pw) + "\" height=\"" +
         Coordinate(ph) + "\" overflow=\"hidden\">\n";
  for (const auto& b : spec.bars) {
    out += "<g class=\"bars\" fill=\"" + EscapeText(b.color) +
           "\" stroke=\"#ffffff\" stroke-width=\"0.5\">";
    const double base = ylog ? ph : sy(0.0);
    for (std::size_t i = 0; i < b.heights.size(); ++i) {
      if (!Drawable(b.edges[i], xlog) || !Drawable(b.edges[i + 1], xlog) ||
          !Drawable(b.heights[i], ylog))
        continue;
      const double x0 = sx(b.edges[i]), x1 = sx(b.edges[i + 1]), y = sy(b.heights[i]);
      out += svg::Rect(std::min(x0, x1), std::min(y, base), std::abs(x1 - x0), std::abs(base - y),
                       "inherit");
    }
    out += "</g>\n";
  }
  for (std::size_t k = 0; k < spec.bands.size(); ++k) {
    const Band& b = spec.bands[k];
    if (band_keep[k].empty()) continue;
    std::string pts;
    for (std::size_t i : band_keep[k])
      pts += Coordinate(sx(b.x[i])) + "," + Coordinate(sy(b.hi[i])) + " ";
    for (auto it = band_keep[k].rbegin(); it != band_keep[k].rend(); ++it)
      pts += Coordinate(sx(b.x[*it])) + "," + Coordinate(sy(b.lo[*it])) + " ";
    pts.pop_back();
    out += "<polygon class=\"band\" points=\"" + pts + "\" fill=\"" + EscapeText(b.color) +
           "\" fill-opacity=\"" + Coordinate(b.opacity) + "\" stroke=\"none\"/>\n";
  }
  for (std::size_t k = 0; k < spec.series.size(); ++k) {
    const PointSeries& s = spec.series[k];
    if (s.line) {
      std::string pts;
      for (std::size_t i : series_keep[k])
        pts += Coordinate(sx(s.x[i])) + "," + Coordinate(sy(s.y[i])) + " ";
      if (!pts.empty()) pts.pop_back();
      out += "<polyline class=\"series\" points=\"" + pts + "\" fill=\"none\" stroke=\"" +
             EscapeText(s.color) + "\" stroke-width=\"1.2\"/>\n";
    } else {
      out += "<g class=\"series\" fill=\"" + EscapeText(s.color) + "\">";
      for (std::size_t i : series_keep[k])
        out += "<circle cx=\"" + Coordinate(sx(s.x[i])) + "\" cy=\"" + Coordinate(sy(s.y[i])) +
               "\" r=\"" + Coordinate(s.radius) + "\"/>";
      out += "</g>\n";
    }
  }
  for (const auto& l : spec.lines) {
    if (!Drawable(l.at, l.vertical ? xlog : ylog)) continue;
    const std::string dash =
        l.dashed ? "class=\"reference\" stroke-dasharray=\"5,3\"" : "class=\"reference\"";
    out += l.vertical ? svg::Line(sx(l.at), 0.0, sx(l.at), ph, EscapeText(l.color), 1.5, dash)
                      : svg::Line(0.0, sy(l.at), pw, sy(l.at), EscapeText(l.color), 1.5, dash);
    out += "\n";
  }
  out += "</svg>\n</g>\n</svg>\n";
  return out;
}

}  // namespace imuconv::report
