#include "summary.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ostream>
#include <string>

namespace imuconv::pipeline {

StepTable::StepTable(std::ostream* o, bool gt_columns) : o_(o) {
  if (!o_) return;
  *o_ << "     k   t_start[s]   dt[s]    |dp|[m]   angle[deg]";
  if (gt_columns) *o_ << "   pos.err[m]   rot.err[deg]";
  *o_ << "\n";
}

void StepTable::row(std::size_t k, std::optional<double> t_start, double dt, double dp, double ang, const GtError* gt) {
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
  *o_ << line << "\n";
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
  std::snprintf(buf, sizeof buf, "%-19s %7.4f %10.5f %12.5f", label.c_str(), sum_dt_, sum_dp_, sum_ang_);
  *o_ << buf;
  if (ngt_) {
    const double ngt = static_cast<double>(ngt_);
    std::snprintf(buf, sizeof buf, " %12.3e %14.3e   rms over %zu interval(s)\n", std::sqrt(se_p_ / ngt),
                  std::sqrt(se_r_ / ngt), ngt_);
    *o_ << buf;
    std::snprintf(buf, sizeof buf, "%-19s %7s %10s %12s %12.3e %14.3e   max\n", "", "", "", "", max_p_, max_r_);
    *o_ << buf;
  } else {
    *o_ << "\n";
  }
}

}  // namespace imuconv::pipeline
