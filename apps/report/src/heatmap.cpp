#include "imuconv/report/heatmap.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

#include "svg_elements.h"

namespace imuconv::report {
namespace {

constexpr double kHeatmapPad = 8.0;
constexpr double kHeatmapCharWidth =
    7.0;  // of an 11 px sans-serif character, generously: labels must not clip
constexpr double kBarWidth = 14.0;
constexpr int kBarSteps =
    64;  // the colour bar as rectangles: no gradient, so no element ids to collide
constexpr double kSwatchRow = 16.0;

std::string EntryName(const std::vector<std::string>& blocks,
                      const std::vector<std::string>& entries, int size, Eigen::Index i) {
  std::string s = blocks[static_cast<std::size_t>(i / size)];
  if (!entries.empty()) s += "." + entries[static_cast<std::size_t>(i % size)];
  return s;
}

std::size_t LongestLabel(const std::vector<std::string>& labels) {
  std::size_t n = 0;
  for (const auto& l : labels) n = std::max(n, l.size());
  return n;
}

}  // namespace

std::string HeatmapSvg(const HeatmapSpec& spec) {
  const Eigen::MatrixXd& m = spec.values;
  const int bs = spec.block_size;
  if (m.size() == 0) throw std::invalid_argument("heatmap: the matrix is empty");
  if (bs < 1 || m.rows() != static_cast<Eigen::Index>(spec.row_blocks.size()) * bs ||
      m.cols() != static_cast<Eigen::Index>(spec.col_blocks.size()) * bs)
    throw std::invalid_argument(
        "heatmap: a " + std::to_string(m.rows()) + "x" + std::to_string(m.cols()) +
        " matrix does not match " + std::to_string(spec.row_blocks.size()) + " row and " +
        std::to_string(spec.col_blocks.size()) + " column blocks of " + std::to_string(bs));
  if (!spec.entry_labels.empty() && static_cast<int>(spec.entry_labels.size()) != bs)
    throw std::invalid_argument("heatmap: entry_labels must be empty or one per entry of a block");

  std::vector<double> all(m.data(), m.data() + m.size());
  const LogColorScale scale = spec.scale ? *spec.scale : LogColorScale::Fit(all);
  const AnchoredScale* anchored = spec.anchored ? &*spec.anchored : nullptr;
  const auto color = [&](double v) { return anchored ? anchored->Color(v) : scale.Color(v); };

  const double c = spec.cell;
  const double title_h = spec.title.empty() ? 0.0 : 22.0;
  const double entry_w =
      spec.entry_labels.empty() ? 0.0 : kHeatmapCharWidth * LongestLabel(spec.entry_labels) + 6.0;
  const double x0 = kHeatmapPad + kHeatmapCharWidth * LongestLabel(spec.row_blocks) + 8.0 + entry_w;
  const double y0 = kHeatmapPad + title_h;
  const double w = c * m.cols(), h = c * m.rows();
  const double label_bottom = y0 + h + (spec.entry_labels.empty() ? 0.0 : 13.0) + 16.0;

  // Counts for the legend: each special kind, and values beyond the scale at either end.
  std::array<int, 5> kind_count{};
  int below = 0, above = 0, beyond_tolerance = 0;
  for (double v : all) {
    const EntryKind k = Classify(v);
    ++kind_count[static_cast<int>(k)];
    if (anchored) {
      if (std::isfinite(v) && anchored->Clamped(v)) (v < anchored->min() ? below : above)++;
      if (!std::isnan(v) && !anchored->WithinTolerance(v)) ++beyond_tolerance;
    } else if (k == EntryKind::value && scale.Clamped(v)) {
      (std::log10(v) < scale.lo_decade() ? below : above)++;
    }
  }
  // Signed anchored values: a negative one is a value, not a special kind.
  if (anchored && anchored->kind() == AnchoredScale::Kind::signed_linear) {
    kind_count[static_cast<int>(EntryKind::value)] +=
        kind_count[static_cast<int>(EntryKind::negative)] +
        kind_count[static_cast<int>(EntryKind::zero)];
    kind_count[static_cast<int>(EntryKind::negative)] =
        kind_count[static_cast<int>(EntryKind::zero)] = 0;
  }

  const double legend_x = x0 + w + 24.0;
  const double bar_y = y0 + 22.0, bar_h = std::max(h - 22.0, 120.0);
  const int decades = scale.hi_decade() - scale.lo_decade();
  const std::string lo_label =
      (below ? "\u2264" : "") + std::string("1e") + std::to_string(scale.lo_decade());
  const std::string hi_label =
      (above ? "\u2265" : "") + std::string("1e") + std::to_string(scale.hi_decade());
  const double tick_w =
      kHeatmapCharWidth * std::max<std::size_t>({lo_label.size(), hi_label.size(), 6});
  int specials =
      anchored ? 1 : 0;  // the anchored legend's line counting the entries beyond the tolerance
  for (EntryKind k :
       {EntryKind::zero, EntryKind::not_a_number, EntryKind::infinite, EntryKind::negative})
    specials += kind_count[static_cast<int>(k)] > 0 ? 1 : 0;
  const double legend_bottom = bar_y + bar_h + 8.0 + specials * kSwatchRow;
  const double width = legend_x + kBarWidth + 6.0 +
                       std::max(tick_w, (anchored ? 17.0 : 9.0) * kHeatmapCharWidth) + kHeatmapPad;
  const double height = std::max(label_bottom, legend_bottom) + kHeatmapPad;

  std::string data_attributes;
  if (anchored)
    data_attributes =
        "data-scale-kind=\"" +
        std::string(anchored->kind() == AnchoredScale::Kind::magnitude ? "magnitude" : "signed") +
        "\" data-scale-min=\"" + Readable(anchored->min(), 6) + "\" data-scale-max=\"" +
        Readable(anchored->max(), 6) + "\" data-tolerance=\"" + Readable(anchored->tolerance(), 6) +
        "\" data-beyond-tolerance=\"" + std::to_string(beyond_tolerance) + "\"";
  std::string out =
      svg::Open(width, height, "heatmap",
                spec.title.empty() ? "heatmap of " + spec.value_name : spec.title, data_attributes);
  if (!spec.title.empty())
    out += svg::Text(x0, kHeatmapPad + 13.0, spec.title, "start", "title", "font-size=\"13\"") + "\n";

  // The cells, row by row.
  out += "<g class=\"cells\">\n";
  for (Eigen::Index i = 0; i < m.rows(); ++i)
    for (Eigen::Index j = 0; j < m.cols(); ++j) {
      const double v = m(i, j);
      // A rect with a <title> child: the hover text.
      std::string rect = svg::Rect(x0 + c * j, y0 + c * i, c, c, color(v).Hex(), "class=\"cell\"");
      rect.resize(rect.size() - 2);  // "/>" becomes ">" + title + "</rect>"
      out += rect + "><title>" +
             EscapeText(EntryName(spec.row_blocks, spec.entry_labels, bs, i) + ", " +
                        EntryName(spec.col_blocks, spec.entry_labels, bs, j) + ": " +
                        spec.value_name + " = " + Readable(v) +
                        (anchored ? (anchored->WithinTolerance(v) ? " (within" : " (BEYOND") +
                                        std::string(" the tolerance ") +
                                        Readable(anchored->tolerance()) + ")"
                                  : std::string())) +
             "</title></rect>\n";
    }
  out += "</g>\n";
  // An exact zero of a magnitude is exact agreement: a dot in its cell, so the calm end's colour
  // is not taken for a missing entry (a fitted scale drew zeros white, like the page).
  if (anchored && anchored->kind() == AnchoredScale::Kind::magnitude &&
      kind_count[static_cast<int>(EntryKind::zero)]) {
    out += "<g class=\"zero-marks\" fill=\"#6b7b8c\">";
    for (Eigen::Index i = 0; i < m.rows(); ++i)
      for (Eigen::Index j = 0; j < m.cols(); ++j)
        if (m(i, j) == 0.0)
          out += "<circle class=\"zero-mark\" cx=\"" + Coordinate(x0 + c * (j + 0.5)) + "\" cy=\"" +
                 Coordinate(y0 + c * (i + 0.5)) + "\" r=\"" + Coordinate(c * 0.12) + "\"/>";
    out += "</g>\n";
  }

  // Block boundaries (white, so the blocks read as the note's figures group them), the frame.
  out += "<g class=\"block-lines\">";
  for (std::size_t b = 1; b < spec.row_blocks.size(); ++b)
    out += svg::Line(x0, y0 + c * bs * b, x0 + w, y0 + c * bs * b, "#ffffff", 2.0);
  for (std::size_t b = 1; b < spec.col_blocks.size(); ++b)
    out += svg::Line(x0 + c * bs * b, y0, x0 + c * bs * b, y0 + h, "#ffffff", 2.0);
  out += svg::Rect(x0, y0, w, h, "none", "stroke=\"#333333\" stroke-width=\"1\"") + "</g>\n";

  // Labels: blocks on both axes, their entries beside them.
  out += "<g class=\"labels\">\n";
  for (std::size_t b = 0; b < spec.row_blocks.size(); ++b)
    out += svg::Text(x0 - entry_w - 6.0, y0 + c * bs * (b + 0.5) + 4.0, spec.row_blocks[b], "end",
                     "row-block") +
           "\n";
  for (std::size_t b = 0; b < spec.col_blocks.size(); ++b)
    out += svg::Text(x0 + c * bs * (b + 0.5), label_bottom - 3.0, spec.col_blocks[b], "middle",
                     "col-block") +
           "\n";
  if (!spec.entry_labels.empty()) {
    for (Eigen::Index i = 0; i < m.rows(); ++i)
      out += svg::Text(x0 - 4.0, y0 + c * (i + 0.5) + 3.5,
                       spec.entry_labels[static_cast<std::size_t>(i % bs)], "end", "row-entry",
                       "font-size=\"9\" fill=\"#555555\"");
    for (Eigen::Index j = 0; j < m.cols(); ++j)
      out += svg::Text(x0 + c * (j + 0.5), y0 + h + 11.0,
                       spec.entry_labels[static_cast<std::size_t>(j % bs)], "middle", "col-entry",
                       "font-size=\"9\" fill=\"#555555\"");
    out += "\n";
  }
  out += "</g>\n";

  // The legend: the colour bar from its bottom to its top with ticks (an anchored scale: its
  // fixed range and the tolerance marked across it; a fitted one: 10^lo to 10^hi, decade ticks),
  // then one swatch per special kind present, with its count.
  out += "<g class=\"legend\">\n";
  if (anchored) {
    out += svg::Text(legend_x, y0 + 8.0,
                     spec.value_name +
                         (anchored->kind() == AnchoredScale::Kind::magnitude ? " (log scale)" : ""),
                     "start", "legend-title") +
           "\n";
    for (int s = 0; s < kBarSteps; ++s) {
      const double t = (s + 0.5) / kBarSteps;
      out += svg::Rect(legend_x, bar_y + bar_h * (1.0 - static_cast<double>(s + 1) / kBarSteps),
                       kBarWidth, bar_h / kBarSteps + 0.5, anchored->ColorAt(t).Hex());
    }
    out += "\n" +
           svg::Rect(legend_x, bar_y, kBarWidth, bar_h, "none",
                     "stroke=\"#333333\" stroke-width=\"0.5\"") +
           "\n";
    const auto ticks = anchored->Ticks();
    for (std::size_t k = 0; k < ticks.size(); ++k) {
      const double y = bar_y + bar_h * (1.0 - ticks[k].first);
      const std::string label = (k == 0 && below ? "\u2264" : "") +
                                std::string(k + 1 == ticks.size() && above ? "\u2265" : "") +
                                ticks[k].second;
      out += svg::Line(legend_x + kBarWidth, y, legend_x + kBarWidth + 4.0, y, "#333333", 1.0) +
             svg::Text(legend_x + kBarWidth + 6.0, y + 4.0, label, "start", "legend-tick") + "\n";
    }
    for (double t : anchored->TolerancePositions()) {
      const double y = bar_y + bar_h * (1.0 - t);
      out += svg::Line(legend_x - 4.0, y, legend_x + kBarWidth + 4.0, y, "#000000", 2.0,
                       "class=\"legend-tolerance\"") +
             svg::Text(legend_x - 6.0, y + 4.0, "tol", "end", "legend-tolerance-label",
                       "font-weight=\"bold\"") +
             "\n";
    }
    const double ty = bar_y + bar_h + 8.0;
    out += svg::Text(legend_x, ty + 9.5,
                     std::to_string(beyond_tolerance) + " beyond tol " +
                         (anchored->kind() == AnchoredScale::Kind::signed_linear ? "\u00b1" : "") +
                         Readable(anchored->tolerance()),
                     "start", "legend-beyond",
                     beyond_tolerance ? "fill=\"#7f0000\" font-weight=\"bold\"" : "") +
           "\n";
  } else {
    out +=
        svg::Text(legend_x, y0 + 8.0, spec.value_name + " (log scale)", "start", "legend-title") +
        "\n";
    for (int s = 0; s < kBarSteps; ++s) {
      const double t = (s + 0.5) / kBarSteps;
      out += svg::Rect(legend_x, bar_y + bar_h * (1.0 - static_cast<double>(s + 1) / kBarSteps),
                       kBarWidth, bar_h / kBarSteps + 0.5, Viridis(t).Hex());
    }
    out += "\n" +
           svg::Rect(legend_x, bar_y, kBarWidth, bar_h, "none",
                     "stroke=\"#333333\" stroke-width=\"0.5\"") +
           "\n";
    const int step = std::max(1, (decades + 7) / 8);  // at most about nine tick labels
    for (int k = scale.lo_decade(); k <= scale.hi_decade(); k += step) {
      const double y = bar_y + bar_h * (1.0 - static_cast<double>(k - scale.lo_decade()) / decades);
      const std::string label = k == scale.lo_decade()   ? lo_label
                                : k == scale.hi_decade() ? hi_label
                                                         : "1e" + std::to_string(k);
      out += svg::Line(legend_x + kBarWidth, y, legend_x + kBarWidth + 4.0, y, "#333333", 1.0) +
             svg::Text(legend_x + kBarWidth + 6.0, y + 4.0, label, "start", "legend-tick") + "\n";
    }
    if ((decades % step) != 0) {  // the top end always labelled
      out += svg::Line(legend_x + kBarWidth, bar_y, legend_x + kBarWidth + 4.0, bar_y, "#333333",
                       1.0) +
             svg::Text(legend_x + kBarWidth + 6.0, bar_y + 4.0, hi_label, "start", "legend-tick") +
             "\n";
    }
  }
  double sy = bar_y + bar_h + 8.0 + (anchored ? kSwatchRow : 0.0);
  for (EntryKind k :
       {EntryKind::zero, EntryKind::not_a_number, EntryKind::infinite, EntryKind::negative}) {
    const int n = kind_count[static_cast<int>(k)];
    if (n == 0) continue;
    const bool exact_zero = anchored && k == EntryKind::zero;  // drawn as the calm end with a dot
    out += "<g class=\"legend-special\">" +
           svg::Rect(legend_x, sy, kBarWidth, 11.0,
                     exact_zero ? anchored->ColorAt(0.0).Hex() : SpecialColor(k).Hex(),
                     "stroke=\"#333333\" stroke-width=\"0.5\"") +
           (exact_zero ? "<circle cx=\"" + Coordinate(legend_x + kBarWidth / 2) + "\" cy=\"" +
                             Coordinate(sy + 5.5) + "\" r=\"2.6\" fill=\"#6b7b8c\"/>"
                       : std::string()) +
           svg::Text(
               legend_x + kBarWidth + 6.0, sy + 9.5,
               std::string(exact_zero ? "0 (exact)" : KindName(k)) + " \u00d7" + std::to_string(n),
               "start", "legend-special-label") +
           "</g>\n";
    sy += kSwatchRow;
  }
  out += "</g>\n</svg>\n";
  return out;
}

}  // namespace imuconv::report
