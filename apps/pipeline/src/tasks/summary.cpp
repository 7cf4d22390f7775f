#include "summary.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ostream>
#include <string>

namespace imuconv::pipeline {

StepTable::StepTable(std::ostream* o, bool gt_columns, std::size_t steps, bool every_row)
    : o_(o), every_row_(every_row || steps <= kFullTableRows) {
  if (!o_) return;
  if (!every_row_)
    *o_ << steps << " steps: the totals"
        << (gt_columns ? " and the worst steps against the ground truth" : "")
        << " (--table prints every row)\n";
  *o_ << "     k   t_start[s]   dt[s]    |dp|[m]   angle[deg]";
  if (gt_columns) *o_ << "   pos.err[m]   rot.err[deg]";
  *o_ << "\n";
}

void StepTable::row(std::size_t k, std::optional<double> t_start, double dt, double dp, double ang,
                    const GtError* gt) {
  sum_dt_ += dt;
  sum_dp_ += dp;
  sum_ang_ += ang;
  if (gt) {
    ++ngt_;
    se_p_ += gt->pos * gt->pos;
    se_r_ += gt->rot * gt->rot;
    max_p_ = std::max(max_p_, gt->pos);
    max_r_ = std::max(max_r_, gt->rot);
  }
  if (!o_) return;
  char buf[256];
  if (t_start)
    std::snprintf(buf, sizeof buf, "%6zu %12.3f %7.4f %10.5f %12.5f", k, *t_start, dt, dp, ang);
  else
    std::snprintf(buf, sizeof buf, "%6zu %12s %7.4f %10.5f %12.5f", k, "-", dt, dp, ang);
  std::string line = buf;
  if (gt) {
    std::snprintf(buf, sizeof buf, " %12.3e %14.3e", gt->pos, gt->rot);
    line += buf;
  }
  if (every_row_) {
    *o_ << line << "\n";
  } else if (gt) {
    keep_if_worse(worst_pos_, {k, line, gt->pos, gt->rot}, &Row::pos);
    keep_if_worse(worst_rot_, {k, std::move(line), gt->pos, gt->rot}, &Row::rot);
  }
}

void StepTable::keep_if_worse(std::vector<Row>& worst, Row r, double Row::*by) const {
  // The kWorstRows largest by `by`, ties to the earlier step: a bounded insertion.
  auto at = std::find_if(worst.begin(), worst.end(), [&](const Row& w) { return r.*by > w.*by; });
  if (at == worst.end() && worst.size() >= kWorstRows) return;
  worst.insert(at, std::move(r));
  if (worst.size() > kWorstRows) worst.pop_back();
}

void StepTable::write_ground_truth_summary(JsonWriter& w) const {
  if (!ngt_) return;
  const double ngt = static_cast<double>(ngt_);
  w.key("ground_truth_summary");
  w.begin_object();
  w.key("intervals");
  w.unsigned_integer(ngt_);
  w.key("rms_position_error_m");
  w.number(std::sqrt(se_p_ / ngt));
  w.key("max_position_error_m");
  w.number(max_p_);
  w.key("rms_rotation_error_deg");
  w.number(std::sqrt(se_r_ / ngt));
  w.key("max_rotation_error_deg");
  w.number(max_r_);
  w.end_object();
}

void StepTable::print_totals(std::size_t n) const {
  if (!o_) return;
  char buf[256];
  const std::string label = " total (" + std::to_string(n) + ")";
  std::snprintf(buf, sizeof buf, "%-19s %7.4f %10.5f %12.5f", label.c_str(), sum_dt_, sum_dp_,
                sum_ang_);
  *o_ << buf;
  if (ngt_) {
    const double ngt = static_cast<double>(ngt_);
    std::snprintf(buf, sizeof buf, " %12.3e %14.3e   rms over %zu interval(s)\n",
                  std::sqrt(se_p_ / ngt), std::sqrt(se_r_ / ngt), ngt_);
    *o_ << buf;
    std::snprintf(buf, sizeof buf, "%-19s %7s %10s %12s %12.3e %14.3e   max\n", "", "", "", "",
                  max_p_, max_r_);
    *o_ << buf;
  } else {
    *o_ << "\n";
  }
  if (every_row_ || worst_pos_.empty()) return;
  // The union of the worst by position and by rotation error, in step order.
  std::vector<const Row*> shown;
  for (const auto* list : {&worst_pos_, &worst_rot_})
    for (const Row& r : *list)
      if (std::none_of(shown.begin(), shown.end(), [&](const Row* s) { return s->k == r.k; }))
        shown.push_back(&r);
  std::sort(shown.begin(), shown.end(), [](const Row* a, const Row* b) { return a->k < b->k; });
  *o_ << "worst steps (the " << kWorstRows << " largest position and the " << kWorstRows
      << " largest rotation errors):\n";
  for (const Row* r : shown) *o_ << r->text << "\n";
}

}  // namespace imuconv::pipeline
