#include "montecarlo_report.h"

#include <cstdio>
#include <string>

namespace imuconv::montecarlo {
namespace {

std::string Fmt(const char* f, double x) {
  char buf[64];
  std::snprintf(buf, sizeof buf, f, x);
  return buf;
}

const char* VerdictName(Verdict v) {
  return v == Verdict::consistent ? "consistent" : "inconsistent";
}

}  // namespace

nlohmann::json ReportJson(const Result& r) {
  using nlohmann::json;
  const Statistics& st = r.stats;
  json blocks = json::array();
  for (const BlockRatio& b : r.blocks)
    blocks.push_back({{"block", b.block},
                      {"variance_ratio", b.variance_ratio},
                      {"axes", {b.axes[0], b.axes[1], b.axes[2]}}});
  json out{{"method", r.method},
           {"method_kind", r.method_kind},
           {"convention", r.convention},
           {"trials", r.trials},
           {"seed", r.seed},
           {"samples", r.samples},
           {"duration", r.duration},
           {"noise_model",
            {{"simulated", r.noise_model.simulated},
             {"matches_prediction", r.noise_model.matches},
             {"noise_scale", r.noise_scale},
             {"note", r.noise_model.note}}},
           {"relative_frobenius", st.relative_frobenius},
           {"nees_mean", st.nees_mean},
           {"nees_bounds", {st.nees_bounds[0], st.nees_bounds[1]}},
           {"nees_confidence", kNeesConfidence},
           {"nees_p_value", st.nees_p_value},
           {"kl", st.kl},
           {"kl_bound", st.kl_bound},
           {"kl_level", kKlLevel},
           {"kl_p_value", st.kl_p_value},
           {"blocks", blocks},
           {"verdict", VerdictName(r.verdict)},
           {"verdict_p_value", r.verdict_p_value},
           {"false_alarm_rate", kFalseAlarmRate},
           {"reasons", r.reasons},
           {"trial_path", r.trial_path}};
  // Only where a plugin's mean-only integration was refused, so that every other run's output
  // keeps its bytes.
  if (!r.mean_only_refused.empty()) out["mean_only_refused"] = r.mean_only_refused;
  return out;
}

void PrintSummary(std::ostream& out, const Result& r) {
  const Statistics& st = r.stats;
  out << "montecarlo: " << r.method << " (" << r.method_kind << "), scored in " << r.convention
      << "\n"
      << "  " << r.trials << " trials, seed " << r.seed << ", " << r.samples << " samples over "
      << Fmt("%.6g", r.duration) << " s\n"
      << "  noise model: " << r.noise_model.simulated
      << (r.noise_model.matches ? "" : " (NOT the prediction's)") << ": " << r.noise_model.note
      << "\n"
      << "  trials: "
      << (r.trial_path == "mean_only"
              ? "the mean only, by " + r.method +
                    "'s increment_mean() (the covariance computed once; its nominal " +
                    (r.mean_only_offset == 0.0 ? std::string("is the full path's bit for bit)")
                                               : "is within " + Fmt("%.2g", r.mean_only_offset) +
                                                     " standard deviations of the full path's)")
              : std::string("the method's full preintegration each") +
                    (r.mean_only_refused.empty()
                         ? std::string()
                         : "; its mean-only integration was not used: " + r.mean_only_refused))
      << "\n\n"
      << "  relative Frobenius error  " << Fmt("%.4g", st.relative_frobenius)
      << "   (|S - Sigma|_F / |Sigma|_F)\n"
      << "  NEES mean                 " << Fmt("%.4g", st.nees_mean) << "   ("
      << Fmt("%.3g", 100 * kNeesConfidence) << "% bounds [" << Fmt("%.4g", st.nees_bounds[0])
      << ", " << Fmt("%.4g", st.nees_bounds[1])
      << "], expected 15; p = " << Fmt("%.3g", st.nees_p_value) << ")\n"
      << "  KL divergence             " << Fmt("%.4g", st.kl) << "   ("
      << Fmt("%.3g", 100 * kKlLevel) << "% bound " << Fmt("%.4g", st.kl_bound)
      << "; p = " << Fmt("%.3g", st.kl_p_value) << ")\n\n"
      << "  block   sample/predicted variance   (x, y, z)\n";
  for (const BlockRatio& b : r.blocks)
    out << "  " << b.block << std::string(8 - std::min<std::size_t>(b.block.size(), 7), ' ')
        << Fmt("%-28.4g", b.variance_ratio) << Fmt("%.3g, ", b.axes[0]) << Fmt("%.3g, ", b.axes[1])
        << Fmt("%.3g", b.axes[2]) << "\n";
  out << "\n  verdict: " << VerdictName(r.verdict) << "   (false-alarm rate at most "
      << Fmt("%.3g", 100 * kFalseAlarmRate)
      << "%: a right covariance is called inconsistent at most this often; p = "
      << Fmt("%.3g", r.verdict_p_value) << ")\n";
  for (const std::string& reason : r.reasons) out << "    - " << reason << "\n";
}

}  // namespace imuconv::montecarlo
