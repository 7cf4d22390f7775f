// imuconv nees (--imu IMU.csv --ground-truth GT.csv --noise NOISE | --pipeline P.json [--noise NOISE])
// --windows L1,L2,... --method M [--convention C] [--stride S] [--json]: windows along real data,
// each propagated from the ground truth, their NEES against chi-square(9) and the factor on the
// noise densities that fits the median (docs/nees.md; the logic is apps/nees/).
// Exit code: 0 success, 2 unusable input (the message names the file and line, the JSON pointer
// or the option). There is no verdict: the factor is the answer.
#include <iostream>
#include <optional>
#include <utility>

#include "commands.h"
#include "exit_codes.h"
#include "imuconv/pipeline/errors.h"
#include "imuconv/pipeline/imu_reader.h"
#include "imuconv/pipeline/json_io.h"
#include "imuconv/pipeline/json_parse.h"
#include "imuconv/printable.h"
#include "imuconv/report/report_output.h"
#include "nees.h"
#include "nees_input.h"
#include "nees_report.h"
#include "imuconv/pipeline/kalibr_yaml.h"
#include "report/pages/pages.h"

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
  static std::string imu_path, gt_path, noise_path, pipeline_path, method_id, convention = "left";
  static std::vector<double> windows;
  static double stride = 0.0;
  static bool as_json = false;
  auto* imu_opt = sub->add_option("--imu", imu_path, "EuRoC/ASL IMU CSV (#timestamp [ns],w_x,w_y,w_z,a_x,a_y,a_z)");
  auto* gt_opt = sub->add_option("--ground-truth", gt_path,
                                 "EuRoC/ASL full-state ground truth (17 fields: time, p, q wxyz, v, bg, ba)");
  sub->add_option("--pipeline", pipeline_path,
                  "Instead of --imu and --ground-truth: a pipeline whose /imu (EuRoC, generic CSV with its column map "
                  "and time unit, or inline), /ground_truth (format euroc), /noise and /gravity are read as imuconv "
                  "run reads them (its tasks are not run)")
      ->excludes(imu_opt)
      ->excludes(gt_opt);
  sub->add_option("--noise", noise_path,
                  "The four noise densities: a JSON noise object (or a pipeline holding one), or a Kalibr imu.yaml "
                  "(.yaml/.yml); with --pipeline, replaces its /noise");
  sub->add_option("--windows", windows, "Window lengths in seconds, comma-separated (e.g. 0.2,0.5,1.0)")
      ->required()
      ->delimiter(',');
  sub->add_option("--method", method_id, "A propagator id")->required();
  sub->add_option("--convention", convention, "State convention of the error and covariance (default: left)");
  sub->add_option("--stride", stride, "Seconds between window starts (default: each window's length)")
      ->check(CLI::PositiveNumber);
  sub->add_flag("--json", as_json, "Print one JSON object (schemas/nees_output.schema.json) instead of the table");
  static std::string report_path;
  sub->add_option("--report", report_path,
                  "Also write a self-contained HTML report: NEES per window against chi-square(9), each error "
                  "component with its +-3 sigma over time, and the summary (replaced atomically)")
      ->type_name("OUT.html")
      ->check(OutputPathCheck());
  AddPluginDirOption(*sub, ctx);
  sub->callback([&ctx] {
    if (pipeline_path.empty() && (imu_path.empty() || gt_path.empty() || noise_path.empty()))
      throw CLI::ValidationError("give --imu, --ground-truth and --noise, or --pipeline P.json");
    nees::Result result;
    std::vector<std::string> imu_warnings;  // suspected units or column order of the samples
    std::optional<report::ReportOutput> report_out;
    try {
      // The report's destination is examined before any work (a directory or an input fails now).
      if (!report_path.empty()) {
        report_out.emplace(report_path);
        for (const std::string* input : {&imu_path, &gt_path, &noise_path, &pipeline_path})
          if (!input->empty()) report_out->RefuseIfSame(*input, "the input file");
      }
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
      const nees::Input in =
          pipeline_path.empty() ? nees::ReadEurocInput(imu_path, gt_path) : nees::ReadPipelineInput(pipeline_path);
      if (!noise_path.empty())
        options.noise = ReadNoise(noise_path);
      else if (in.noise)
        options.noise = *in.noise;
      else
        throw Error(pipeline_path + ": /noise: required key is missing (or give --noise)");
      options.gravity = in.gravity;
      imu_warnings = in.imu.warnings;
      PrintWarnings(imu_warnings);
      result = nees::RunNees(reg, in.imu, in.gt, options);
      if (report_out) {
        report_out->RefuseIfLoadedObject();
        report::Inputs inputs;
        for (const auto& [role, path] : {std::pair<const char*, const std::string*>{"imu", &imu_path},
                                         {"ground truth", &gt_path},
                                         {"noise", &noise_path},
                                         {"pipeline", &pipeline_path}})
          if (!path->empty()) inputs.push_back({role, *path});
        report_out->Write(report::NeesPage(result, inputs));
        if (!ctx.quiet()) std::cerr << "wrote " << Printable(report_path) << "\n";
      }
    } catch (const std::exception& e) {
      ctx.exit_code = ReportFailure(e);
      return;
    }
    if (as_json)
      std::cout << WithWarnings(nees::ReportJson(result), imu_warnings).dump(1) << "\n";
    else
      nees::PrintSummary(std::cout, result);
    ctx.exit_code = 0;
  });
}

}  // namespace imuconv::cli
