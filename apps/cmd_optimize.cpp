// imuconv optimize (--imu IMU.csv --poses POSES.csv | --pipeline P.json) --noise NOISE
// --keyframe-step S [--pose-sigma METRES,RADIANS] [--method M] [--convention C] [--json] [-o OUT]
// [--report OUT.html]: every keyframe's state over a sequence from preintegration factors and
// pose measurements, solved with Ceres, with each keyframe's marginal covariance (docs/optimize.md;
// the logic is apps/optimize/).
// Exit code: 0 converged, 1 the solve did not converge (said in the output), 2 unusable input
// (the message names the file and line, the JSON pointer or the option), 3 internal error.
#include "imuconv/cli/cmd_optimize.h"

#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <utility>

#include "imuconv/cli/exit_codes.h"
#include "imuconv/optimize/optimize.h"
#include "imuconv/optimize/optimize_input.h"
#include "imuconv/optimize/optimize_output.h"
#include "imuconv/optimize/optimize_page.h"
#include "imuconv/optimize/pipeline_task.h"
#include "imuconv/pipeline/output_file.h"
#include "imuconv/printable.h"
#include "judgment.h"
#include "nees_input.h"
#include "report_destination.h"

namespace imuconv::cli {

int RunOptimizeCommand(const CommandContext& ctx, const OptimizeCommandOptions& o) {
  if (o.pipeline_path.empty() && (o.imu_path.empty() || o.poses_path.empty()))
    throw UsageError{"give --imu and --poses, or --pipeline P.json"};
  if (o.pipeline_path.empty() && o.noise_path.empty())
    throw UsageError{
        "give --noise (a JSON noise object, a pipeline holding one, or a Kalibr imu.yaml)"};
  if (!o.pose_sigma.empty() && o.pose_sigma.size() != 2)
    throw UsageError{"--pose-sigma: give two numbers, METRES,RADIANS (e.g. 0.01,0.01)"};
  if (o.residual != "gtsam" && o.residual != "forster")
    throw UsageError{"--residual: gtsam or forster, not '" + Printable(o.residual) + "'"};
  const optimize::PageInputs inputs = GivenInputs({{"imu", &o.imu_path},
                                                   {"poses", &o.poses_path},
                                                   {"noise", &o.noise_path},
                                                   {"pipeline", &o.pipeline_path}});
  return Judge(o.as_json, [&] {
    // Both destinations are examined before any work: a directory, an input's own name or the
    // other output's fails now.
    ReportDestination report(o.report_path);
    std::optional<pipeline::OutputFile> out;
    if (!o.output_path.empty()) {
      out.emplace(o.output_path);
      report.RefuseIfSameOutput(*out, "-o");
    }
    for (const auto& input : inputs) {
      report.RefuseIfSame(input.second, "the " + input.first + " file");
      if (out) out->refuse_if_same(input.second, "the " + input.first + " file");
    }
    Registry reg;
    LoadRegistryWithStateConvention(reg, ctx, o.convention);
    const optimize::Input in = o.pipeline_path.empty()
                                   ? optimize::ReadFileInput(o.imu_path, o.poses_path)
                                   : optimize::ReadPipelineInput(o.pipeline_path);
    optimize::Options options;
    options.noise = nees::NoiseGivenOrInPipeline(o.noise_path, in.noise, o.pipeline_path);
    options.method = o.method;
    options.convention = o.convention;
    options.kind = o.residual == "forster" ? ResidualKind::Forster : ResidualKind::Gtsam;
    options.keyframe_step = o.keyframe_step;
    if (o.pose_sigma.size() == 2) {
      options.pose_sigma_m = o.pose_sigma[0];
      options.pose_sigma_rad = o.pose_sigma[1];
    }
    options.reintegrate_gyro = o.reintegrate_gyro;
    options.reintegrate_accel = o.reintegrate_accel;
    options.max_rounds = o.max_rounds;
    options.max_iterations = o.max_iterations;
    options.gravity = in.gravity;
    Judgment judgment;
    judgment.warnings = in.warnings;
    PrintWarnings(judgment.warnings);
    const auto result = std::make_shared<const optimize::Result>(
        optimize::RunOptimize(reg, in.imu, in.poses, options));
    report.Write([&] { return optimize::OptimizePage(*result, inputs); }, ctx);
    judgment.SetResult(result, optimize::ResultJson, optimize::PrintTable);
    judgment.exit_code = result->converged ? kExitOk : kExitInconsistent;
    if (out) {
      std::ostringstream text;
      if (o.as_json)
        text << WithWarnings(judgment.json(), judgment.warnings).dump(1) << "\n";
      else
        judgment.print_table(text);
      out->refuse_if_loaded_object();
      out->write(text.str());
      std::cout.flush();
      out->commit();
      if (!ctx.quiet() && !out->is_stdout())
        std::cerr << "wrote " << Printable(o.output_path) << "\n";
      judgment.printed_elsewhere = true;
    }
    if (!result->converged)
      PrintWarnings({"the solve did not converge (" + result->solver_message +
                     "): the output holds where it stopped, not an optimum"});
    return judgment;
  });
}

// The command line of imuconv optimize: its description, and its flags onto the options.
static void DeclareOptimizeCommand(CLI::App* sub, OptimizeCommandOptions* o) {
  sub->description(
      "Estimate every keyframe's state (velocity and biases, and the poses) over a sequence "
      "from preintegration factors and pose measurements, with Ceres");
  auto* imu_opt = AddImuCsvOption(*sub, o->imu_path);
  auto* poses_opt = sub->add_option(
      "--poses", o->poses_path,
      "The pose measurements: EuRoC/ASL ground truth (17 fields; its biases are then the "
      "report's reference), EuRoC vicon0 (8 comma-separated fields) or a TUM trajectory (t x y z "
      "qx qy qz qw), told apart by the first data row");
  sub->add_option("--pipeline", o->pipeline_path,
                  "Instead of --imu and --poses: a pipeline whose /imu, /ground_truth (the "
                  "poses), /noise and /gravity are read as imuconv run reads them")
      ->excludes(imu_opt)
      ->excludes(poses_opt);
  AddNoiseFileOption(*sub, o->noise_path);
  sub->add_option("--keyframe-step", o->keyframe_step,
                  "Seconds between keyframes: every interval must hold an IMU sample strictly "
                  "inside (a step longer than the longest sample period does), at most the "
                  "data's span and at most 1e6 keyframes")
      ->required();
  sub->add_option("--pose-sigma", o->pose_sigma,
                  "Standard deviations of the pose measurements, METRES,RADIANS (default "
                  "0.01,0.01; each at least 1e-9)")
      ->delimiter(',');
  sub->add_option("--method", o->method,
                  "A propagator (preintegration by propagation) or preintegrator id (default "
                  "manifold)");
  sub->add_option("--convention", o->convention,
                  "The state convention the solver steps in and the covariances are given in "
                  "(default left); the optimum does not depend on it");
  sub->add_option("--residual", o->residual,
                  "The preintegration residual: gtsam (default) or forster");
  sub->add_option("--reintegrate-gyro", o->reintegrate_gyro,
                  "Re-integrate a factor when its start gyro bias moved more than this, rad/s "
                  "(default 0.01, VINS-Fusion's)")
      ->check(CLI::PositiveNumber);
  sub->add_option("--reintegrate-accel", o->reintegrate_accel,
                  "Re-integrate a factor when its start accelerometer bias moved more than this, "
                  "m/s^2 (default 0.10, VINS-Fusion's)")
      ->check(CLI::PositiveNumber);
  sub->add_option("--max-rounds", o->max_rounds,
                  "Solves at most: the first, and one after each re-integration (default 4)")
      ->check(CLI::Range(1, 100));
  sub->add_option("--max-iterations", o->max_iterations,
                  "Levenberg-Marquardt iterations per solve at most (default 100); a solve that "
                  "stops on it has not converged, which the output says (exit 1)")
      ->check(CLI::Range(1, 100000));
  sub->add_flag("--json", o->as_json,
                "Print one JSON object (its keyframes the list \"keyframes\", docs/optimize.md) "
                "instead of the table");
  AddOutputPathOption(
      *sub, "-o,--output", o->output_path,
      "Write the table or JSON to this file (replaced atomically) instead of stdout", "OUT");
  AddReportOption(*sub, o->report_path,
                  "each estimated bias over time with its +-3 sigma band, against the ground "
                  "truth's biases when the poses file has them, and the solver summary (replaced "
                  "atomically)");
  // The pipeline's optimize tasks (`imuconv run`) are solved by this command's library.
  optimize::RegisterPipelineTask();
}

void RegisterOptimizeCommand(CLI::App& app, CommandContext& ctx) {
  AddCommand(app, ctx, "optimize", DeclareOptimizeCommand, RunOptimizeCommand);
}

}  // namespace imuconv::cli
