// The nees report (nees_report.h).
#include "nees_report.h"

#include <cmath>
#include <cstdio>

#include "imuconv/pipeline/json_io.h"
#include "split_factors.h"

namespace imuconv::nees {
namespace {

// A factor or statistic that may be undefined (NaN): JSON null.
nlohmann::json NumberOrNull(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
}

nlohmann::json Vector(const Vec9& v) { return std::vector<double>(v.data(), v.data() + 9); }

}  // namespace

const char* const kOffsetCauses =
    "a systematic offset no noise scale explains. Common causes: a bias error in the ground truth "
    "(its biases\n"
    "start every window), a misaligned gravity or body frame, a time offset between the IMU and "
    "the ground truth.\n"
    "Which one it is cannot be told from these numbers alone.";

nlohmann::json ReportJson(const Result& r) {
  using nlohmann::json;
  json windows = json::array();
  for (const WindowLengthResult& w : r.windows) {
    json components = json::array();
    for (const ComponentStatistics& c : w.components)
      components.push_back({{"name", c.name},
                            {"mean_standardized", NumberOrNull(c.mean_standardized)},
                            {"rms_standardized", NumberOrNull(c.rms_standardized)},
                            {"positive", c.positive},
                            {"nonzero", c.nonzero},
                            {"sign_p_value", c.sign_p_value},
                            {"offset", c.offset}});
    json error = json::array(), sigma = json::array(), cov_gyro = json::array(),
         cov_accel = json::array();
    for (std::size_t i = 0; i < w.error.size(); ++i) {
      error.push_back(Vector(w.error[i]));
      sigma.push_back(Vector(w.sigma[i]));
    }
    for (const Mat9& m : w.cov_gyro) cov_gyro.push_back(pipeline::MatrixToJson(m));
    for (const Mat9& m : w.cov_accel) cov_accel.push_back(pipeline::MatrixToJson(m));
    json entry = {{"length", w.length},
                  {"stride", w.stride},
                  {"count", w.nees.size()},
                  {"median", w.median},
                  {"mean", w.mean},
                  {"p95", w.p95},
                  {"fraction_inside", w.fraction_inside},
                  {"factor", w.factor},
                  {"factors",
                   {{"all", w.factor},
                    {"gyro", NumberOrNull(w.factor_gyro)},
                    {"accel", NumberOrNull(w.factor_accel)}}},
                  {"components", components},
                  {"t_start", w.t_start},
                  {"nees", w.nees},
                  {"error", error},
                  {"sigma", sigma},
                  {"cov_gyro", cov_gyro},
                  {"cov_accel", cov_accel}};
    // Only when there are some: a run on data without gaps prints what it always printed.
    if (w.skipped_in_gap > 0) entry["skipped_in_gap"] = w.skipped_in_gap;
    windows.push_back(std::move(entry));
  }
  return json{{"method", r.method},
              {"convention", r.convention},
              {"error_blocks", {"p", "theta", "v"}},
              {"noise",
               {{"gyro_noise_density", r.noise.gyro_noise_density},
                {"accel_noise_density", r.noise.accel_noise_density},
                {"gyro_random_walk", r.noise.gyro_random_walk},
                {"accel_random_walk", r.noise.accel_random_walk}}},
              {"span", {r.t_begin, r.t_end}},
              {"chi2",
               {{"dof", kDof},
                {"confidence", kConfidence},
                {"median", r.chi2.median},
                {"lower", r.chi2.lower},
                {"upper", r.chi2.upper}}},
              {"offset_rule", kOffsetRule},
              {"windows", windows}};
}

std::vector<std::string> SkippedWindows(const Result& r) {
  std::vector<std::string> lines;
  for (const WindowLengthResult& w : r.windows) {
    if (w.skipped_in_gap == 0) continue;
    char line[256];
    std::snprintf(line, sizeof line,
                  "%.9g s windows: %zu of %zu reach into a gap in the data (IMU samples more "
                  "than 10 median periods apart) and are skipped, the first starting at %.9g s; "
                  "the statistics are over the other %zu",
                  w.length, w.skipped_in_gap, w.skipped_in_gap + w.nees.size(), w.first_skipped,
                  w.nees.size());
    lines.push_back(line);
  }
  return lines;
}

void PrintSummary(std::ostream& out, const Result& r) {
  char line[256];
  out << "nees: " << r.method << " in the " << r.convention << " chart, error [p, theta, v] ("
      << kDof << " dof)\n";
  std::snprintf(line, sizeof line, "chi-square(%d): median %.4f, %.0f %% bounds [%.4f, %.4f]\n",
                kDof, r.chi2.median, 100 * kConfidence, r.chi2.lower, r.chi2.upper);
  out << line;
  std::snprintf(line, sizeof line, "%10s %10s %7s %12s %12s %12s %8s %8s\n", "window s", "stride s",
                "count", "median", "mean", "p95", "inside", "factor");
  out << line;
  for (const WindowLengthResult& w : r.windows) {
    std::snprintf(line, sizeof line, "%10.4g %10.4g %7zu %12.4g %12.4g %12.4g %7.1f%% %8.4g\n",
                  w.length, w.stride, w.nees.size(), w.median, w.mean, w.p95,
                  100 * w.fraction_inside, w.factor);
    out << line;
  }
  for (const std::string& skipped : SkippedWindows(r)) out << skipped << "\n";
  out << "factor k: the one scale on all four noise densities that puts the median NEES on the "
         "chi-square median\n"
         "(NEES scales as 1/k^2). k > 1: the data's errors are larger than the declared densities "
         "predict, so\n"
         "multiply the densities by k; k < 1: the densities are pessimistic. Datasheet densities "
         "are known to be\n"
         "optimistic on real data (unmodelled vibration, temperature, axis misalignment, "
         "ground-truth error).\n";
  std::snprintf(line, sizeof line,
                "chi-square(3) median %.4f: each sensor's factor is fitted on one 3-dof block\n",
                ChiSquare3Median());
  out << "\n" << line;
  for (const WindowLengthResult& w : r.windows) {
    std::snprintf(line, sizeof line,
                  "%.4g s windows: k_all %.4g, k_gyro %.4g (theta block), k_accel %.4g (v block)\n",
                  w.length, w.factor, w.factor_gyro, w.factor_accel);
    out << line;
    if (w.components.empty()) {
      out << "  (no per-sensor fit: a sensor's densities are all zero)\n";
      continue;
    }
    for (const ComponentStatistics& c : w.components) {
      std::snprintf(line, sizeof line,
                    "  %-8s mean %+8.3f  rms %7.3f  %6zu of %-6zu positive  sign test p %9.3g%s\n",
                    c.name.c_str(), c.mean_standardized, c.rms_standardized, c.positive, c.nonzero,
                    c.sign_p_value, c.offset ? "  OFFSET" : "");
      out << line;
    }
  }
  out << "k_gyro scales the gyro densities (white noise and random walk) so theta's median NEES is "
         "chi-square(3)'s;\n"
         "k_accel then scales the accelerometer's so v's is. Components: each error over its sigma "
         "under the two\n"
         "factors, across windows (mean ~0 and rms ~1 if the noise explains it).\n"
         "OFFSET: "
      << kOffsetRule << ";\n"
      << kOffsetCauses << "\n";
}

}  // namespace imuconv::nees
