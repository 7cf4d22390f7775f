// imuconv bench [--json] [--benchmark-args=...]: the benchmark set of bench/ (same code, same
// names), run by the separate imuconv-bench program next to this one. The user's tool does
// not link Google Benchmark: only imuconv-bench needs it at run time.
#include <unistd.h>

#include <filesystem>
#include <iostream>
#include <string>
#include <system_error>
#include <vector>

#include "imuconv/cli/commands.h"
#include "imuconv/cli/exit_codes.h"
#include "imuconv/printable.h"

namespace imuconv::cli {
namespace {

/// imuconv-bench beside the running executable (the build tree's bin/, or the prefix's bin/).
std::filesystem::path BenchProgram() {
  std::error_code ec;
  const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (ec) return {};
  return self.parent_path() / "imuconv-bench";
}

int RunBench(bool as_json, const std::vector<std::string>& passthrough) {
  const std::filesystem::path program = BenchProgram();
  std::error_code ec;
  if (program.empty() || !std::filesystem::is_regular_file(program, ec) ||
      access(program.c_str(), X_OK) != 0) {
    PrintError(
        "imuconv bench runs the benchmark program imuconv-bench, which is not beside this imuconv" +
        (program.empty() ? std::string() : " (" + Printable(program.string()) + ")") +
        "; it is built with the project (target imuconv_bench) and installed beside imuconv");
    return kExitInternal;  // an incomplete installation, not the input
  }
  std::vector<std::string> args{program.string()};
  if (as_json) args.push_back("--benchmark_format=json");
  args.insert(args.end(), passthrough.begin(), passthrough.end());
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  std::cout.flush();
  std::cerr.flush();
  execv(program.c_str(), argv.data());  // returns only on failure
  PrintError("cannot run " + Printable(program.string()) + ": " +
             std::system_category().message(errno));
  return kExitInternal;
}

}  // namespace

void RegisterBenchCommand(CLI::App& app, CommandContext& ctx) {
  auto* sub = app.add_subcommand("bench",
                                 "Run the benchmark set (ns per IMU sample) with imuconv-bench; "
                                 "extra flags go to Google Benchmark");
  static bool as_json = false;
  static std::vector<std::string> passthrough;
  sub->add_flag("--json", as_json, "Print Google Benchmark's JSON report");
  sub->add_option("--benchmark-args", passthrough,
                  "Arguments passed to Google Benchmark, e.g. --benchmark_filter=BM_Propagate")
      ->allow_extra_args(true);
  sub->callback([&ctx] { ctx.exit_code = RunBench(as_json, passthrough); });
}

}  // namespace imuconv::cli
