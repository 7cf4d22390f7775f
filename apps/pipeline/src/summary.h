// The human summary's table of steps (propagate_by_preintegration), printed row by row as the
// steps are written (nothing per step is held), with totals summed in index order. The other
// tasks' summaries are one line each, printed by the task.
#pragma once

#include <cstddef>
#include <iosfwd>
#include <optional>

#include "forms/comparison.h"
#include "imuconv/pipeline/json_writer.h"

namespace imuconv::pipeline {

class StepTable {
 public:
  /// Prints the header to `o` (may be null: only the totals are kept). The ground-truth
  /// columns are shown when a comparison is possible at all (`gt_columns`): rows are
  /// printed before all steps are known.
  StepTable(std::ostream* o, bool gt_columns);
  /// Step k: its start time (when known), dt, |dp|, rotation angle and, when compared with
  /// the ground truth, its errors.
  void row(std::size_t k, std::optional<double> t_start, double dt, double dp, double angle_deg, const GtError* gt);
  /// "ground_truth_summary" (rms and max errors) of the open object, when a step was compared.
  void write_ground_truth_summary(JsonWriter& w) const;
  /// The totals line(s) after n steps.
  void print_totals(std::size_t n) const;

 private:
  std::ostream* o_;
  std::size_t ngt_ = 0;
  double se_p_ = 0, se_r_ = 0, max_p_ = 0, max_r_ = 0, sum_dt_ = 0, sum_dp_ = 0, sum_ang_ = 0;
};

}  // namespace imuconv::pipeline
