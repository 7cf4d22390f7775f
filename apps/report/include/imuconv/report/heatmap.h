// A heatmap of a matrix's entries as an SVG element, drawn the way the note's figures show the
// entrywise difference d of two matrices (J. Huai, "IMU Propagation as Preintegration",
// section 4): one cell per entry, the rows and columns grouped into labelled blocks (the five
// 3-blocks of a 15x15 covariance, the three by two of a 9x6 bias Jacobian), the colour the
// value's decade (color_scale.h) and a legend with the decades and each special kind present
// (0, NaN, inf, negative) and how many entries have it. Each cell carries a <title> with its
// row, column and value, which a browser shows on hover: no script is needed.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "imuconv/report/anchored_scale.h"
#include "imuconv/report/color_scale.h"

namespace imuconv::report {

struct HeatmapSpec {
  Eigen::MatrixXd values;
  /// Block labels along each axis; each covers `block_size` consecutive rows (columns), so
  /// values.rows() == row_blocks.size() * block_size (likewise for the columns).
  std::vector<std::string> row_blocks, col_blocks;
  int block_size = 3;
  /// Labels of the entries within a block ("x", "y", "z"); empty, or one per entry of a block.
  std::vector<std::string> entry_labels = {"x", "y", "z"};
  std::string title;             ///< above the map; may be empty
  std::string value_name = "d";  ///< what the legend calls the value
  /// The colour scale; by default LogColorScale::Fit over the values. Give one to draw several
  /// heatmaps on one scale.
  std::optional<LogColorScale> scale;
  /// A scale anchored to the matrix kind and the judgment's tolerance (anchored_scale.h); when
  /// given, it is used instead of `scale`, its legend marks the tolerance and counts the entries
  /// beyond it, and the <svg> carries data-scale-min, data-scale-max and data-tolerance. Every
  /// heatmap a judgment is read from should have one (a fitted scale paints round-off and a
  /// failure alike).
  std::optional<AnchoredScale> anchored;
  double cell = 22.0;  ///< cell side, px
};

/// The heatmap as one <svg> element (no XML declaration: for inline use in HTML), every label
/// escaped. Throws std::invalid_argument when the matrix is empty or its size does not match
/// the blocks, or entry_labels is neither empty nor block_size long.
std::string HeatmapSvg(const HeatmapSpec& spec);

}  // namespace imuconv::report
