// The human summary's table of steps (propagate_by_preintegration), with totals summed in
// index order. Up to kFullTableRows steps (or with --table) every row is printed as the step
// is written; beyond, only the totals and the worst steps against the ground truth (at most
// 2 kWorstRows rows held, whatever the number of steps). The other tasks' summaries are one
// line each, printed by the task.
#pragma once

#include <cstddef>
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

#include "../forms/comparison.h"
#include "imuconv/pipeline/json_writer.h"

namespace imuconv::pipeline {

class StepTable {
 public:
  static constexpr std::size_t kFullTableRows = 50;
  static constexpr std::size_t kWorstRows = 5;
  /// Prints the header to `o` (may be null: only the totals are kept). The ground-truth
  /// columns are shown when a comparison is possible at all (`gt_columns`): rows are
  /// printed before all steps are known. `steps`: how many rows will come; `every_row`
  /// prints them all however many.
  StepTable(std::ostream* o, bool gt_columns, std::size_t steps, bool every_row);
  /// Step k: its start time (when known), dt, |dp|, rotation angle and, when compared with
  /// the ground truth, its errors.
  void row(std::size_t k, std::optional<double> t_start, double dt, double dp, double angle_deg,
           const GtError* gt);
  /// "ground_truth_summary" (rms and max errors) of the open object, when a step was compared.
  void write_ground_truth_summary(JsonWriter& w) const;
  /// The totals line(s) after n steps, then (in the short form) the worst steps.
  void print_totals(std::size_t n) const;

 private:
  struct Row {
    std::size_t k;
    std::string text;
    double pos, rot;
  };
  void keep_if_worse(std::vector<Row>& worst, Row r, double Row::*by) const;
  std::ostream* o_;
  bool every_row_;
  std::vector<Row> worst_pos_, worst_rot_;
  std::size_t ngt_ = 0;
  double se_p_ = 0, se_r_ = 0, max_p_ = 0, max_r_ = 0, sum_dt_ = 0, sum_dp_ = 0, sum_ang_ = 0;
};

}  // namespace imuconv::pipeline
