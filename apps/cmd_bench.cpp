// imuconv bench [--json] [Google Benchmark flags]: the benchmark set of bench/ (same code,
// same names), run from the installed tool against the installed plugins.
#include <string>
#include <vector>

#include "commands.h"
#include "suite.h"

namespace imuconv::cli {

void RegisterBenchCommand(CLI::App& app, CommandContext& ctx) {
  auto* sub = app.add_subcommand("bench", "Run the benchmark set (ns per IMU sample); extra flags go to Google Benchmark");
  static bool as_json = false;
  static std::vector<std::string> passthrough;
  sub->add_flag("--json", as_json, "Print Google Benchmark's JSON report");
  sub->add_option("--benchmark-args", passthrough, "Arguments passed to Google Benchmark, e.g. --benchmark_filter=BM_Propagate")
      ->allow_extra_args(true);
  sub->callback([&ctx] {
    std::vector<std::string> args{"imuconv bench"};
    if (as_json) args.push_back("--benchmark_format=json");
    args.insert(args.end(), passthrough.begin(), passthrough.end());
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    ctx.exit_code = bench::Main(static_cast<int>(argv.size()), argv.data());
  });
}

}  // namespace imuconv::cli
