// The nees report (nees_report.h).
#include "nees_report.h"

#include <cstdio>

namespace imuconv::nees {

nlohmann::json ReportJson(const Result& r) {
  using nlohmann::json;
  json windows = json::array();
  for (const WindowLengthResult& w : r.windows)
    windows.push_back({{"length", w.length},
                       {"stride", w.stride},
                       {"count", w.nees.size()},
                       {"median", w.median},
                       {"mean", w.mean},
                       {"p95", w.p95},
                       {"fraction_inside", w.fraction_inside},
                       {"factor", w.factor},
                       {"t_start", w.t_start},
                       {"nees", w.nees}});
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
              {"windows", windows}};
}

void PrintSummary(std::ostream& out, const Result& r) {
  char line[256];
  out << "nees: " << r.method << " in the " << r.convention << " chart, error [p, theta, v] (" << kDof << " dof)\n";
  std::snprintf(line, sizeof line, "chi-square(%d): median %.4f, %.0f %% bounds [%.4f, %.4f]\n", kDof, r.chi2.median,
                100 * kConfidence, r.chi2.lower, r.chi2.upper);
  out << line;
  std::snprintf(line, sizeof line, "%10s %10s %7s %12s %12s %12s %8s %8s\n", "window s", "stride s", "count", "median",
                "mean", "p95", "inside", "factor");
  out << line;
  for (const WindowLengthResult& w : r.windows) {
    std::snprintf(line, sizeof line, "%10.4g %10.4g %7zu %12.4g %12.4g %12.4g %7.1f%% %8.4g\n", w.length, w.stride,
                  w.nees.size(), w.median, w.mean, w.p95, 100 * w.fraction_inside, w.factor);
    out << line;
  }
  out << "factor k: the one scale on all four noise densities that puts the median NEES on the chi-square median\n"
         "(NEES scales as 1/k^2). k > 1: the data's errors are larger than the declared densities predict, so\n"
         "multiply the densities by k; k < 1: the densities are pessimistic. Datasheet densities are known to be\n"
         "optimistic on real data (unmodelled vibration, temperature, axis misalignment, ground-truth error).\n";
}

}  // namespace imuconv::nees
