// imuconv nees --imu IMU.csv --ground-truth GT.csv --noise NOISE --windows L1,L2,... --method M
// [--convention C] [--stride S] [--json]: windows along real data, each propagated from the ground
// truth, their NEES against chi-square(9) and the factor on the noise densities that fits the
// median (docs/nees.md; the logic is apps/nees/).
// Exit code: 0 success, 2 unusable input (the message names the file and line, the JSON pointer
// or the option). There is no verdict: the factor is the answer.
#include <iostream>

#include "commands.h"
#include "imuconv/pipeline/errors.h"
#include "imuconv/pipeline/imu_reader.h"
#include "imuconv/pipeline/json_io.h"
#include "imuconv/printable.h"
#include "nees.h"
#include "nees_report.h"
#include "pipeline/src/data/kalibr_yaml.h"

namespace imuconv::cli {
namespace {

bool EndsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// A Kalibr imu.yaml (by extension), else a JSON file holding a pipeline's "noise" object, or a
// whole pipeline whose /noise is one.
ImuNoise ReadNoise(const std::string& path) {
  if (EndsWith(path, ".yaml") || EndsWith(path, ".yml")) return pipeline::data::ReadKalibrImuYaml(path);
  return pipeline::ReadJsonFileAs(path, [](const pipeline::Node& root) {
    if (root.has("noise")) return pipeline::NoiseFromJson(root["noise"]);
    return pipeline::NoiseFromJson(root);
  });
}

}  // namespace

void RegisterNeesCommand(CLI::App& app, CommandContext& ctx) {
  auto* sub = app.add_subcommand(
      "nees", "Propagate windows of real data from the ground truth and fit the noise densities' scale to their NEES");
  static std::string imu_path, gt_path, noise_path, method_id, convention = "left";
  static std::vector<double> windows;
  static double stride = 0.0;
  static bool as_json = false;
  sub->add_option("--imu", imu_path, "EuRoC/ASL IMU CSV (#timestamp [ns],w_x,w_y,w_z,a_x,a_y,a_z)")->required();
  sub->add_option("--ground-truth", gt_path,
                  "EuRoC/ASL full-state ground truth (17 fields: time, p, q wxyz, v, bg, ba)")
      ->required();
  sub->add_option("--noise", noise_path,
                  "The four noise densities: a JSON noise object (or a pipeline holding one), or a Kalibr imu.yaml")
      ->required();
  sub->add_option("--windows", windows, "Window lengths in seconds, comma-separated (e.g. 0.2,0.5,1.0)")
      ->required()
      ->delimiter(',');
  sub->add_option("--method", method_id, "A propagator id")->required();
  sub->add_option("--convention", convention, "State convention of the error and covariance (default: left)");
  sub->add_option("--stride", stride, "Seconds between window starts (default: each window's length)")
      ->check(CLI::PositiveNumber);
  sub->add_flag("--json", as_json, "Print one JSON object (schemas/nees_output.schema.json) instead of the table");
  AddPluginDirOption(*sub, ctx);
  sub->callback([&ctx] {
    nees::Result result;
    try {
      Registry reg;
      const std::vector<LoadIssue> issues = LoadRegistry(reg, ctx);
      for (const auto& i : issues)
        std::cerr << "imuconv: warning: " << Printable(i.file) << ": " << Printable(i.message) << "\n";
      const std::string unknown = UnknownConventionMessage(reg, PluginKind::StateConvention, convention, issues);
      if (!unknown.empty()) throw Error("--convention: " + unknown);
      nees::Options options;
      options.method = method_id;
      options.convention = convention;
      options.window_lengths = windows;
      options.stride = stride;
      options.noise = ReadNoise(noise_path);
      const pipeline::ImuData imu = pipeline::ReadEurocImu(imu_path);
      const pipeline::GroundTruth gt = pipeline::ReadEurocGroundTruth(gt_path, *imu.origin);
      result = nees::RunNees(reg, imu, gt, options);
    } catch (const std::exception& e) {
      PrintError(e.what());
      ctx.exit_code = 2;
      return;
    }
    if (as_json)
      std::cout << nees::ReportJson(result).dump(1) << "\n";
    else
      nees::PrintSummary(std::cout, result);
    ctx.exit_code = 0;
  });
}

}  // namespace imuconv::cli
