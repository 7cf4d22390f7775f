// imuconv run PIPELINE.json [-o OUT.json|OUT.npz] [--format json|npz] [--tum TRAJ.txt]
// [--errors ERRORS.csv] [--shard K/N]: runs a JSON pipeline (or one shard of its tasks, which
// imuconv merge joins); the result as JSON or as a NumPy .npz of its arrays
// (imuconv/pipeline/result_arrays.h); optionally also writes one propagate_by_preintegration task's
// predictions as a TUM trajectory (what evo reads) and its per-step errors against the ground truth
// as CSV. Exit code: 0, or 3 when a check task found an inconsistency (the output written all the
// same); 1 a failed run (nothing written), 2 a usage error.
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cinttypes>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <string_view>
#include <tuple>
#include <utility>

#include "imuconv/cli/commands.h"
#include "imuconv/cli/exit_codes.h"
#include "imuconv/pipeline/output_file.h"
#include "imuconv/pipeline/pipeline.h"
#include "imuconv/pipeline/result_arrays.h"
#include "imuconv/printable.h"
#include "imuconv/so3.h"

namespace imuconv::cli {
namespace {

struct RunCommandOptions {
  std::string pipeline, output, format, tum, errors, trajectory_task, shard;
  bool quiet = false, every_row = false;
  unsigned threads = 0;
};

/// The task whose steps --tum / --errors write: --trajectory-task, or the only one there is.
std::string TrajectoryTask(const pipeline::Pipeline& p, const RunCommandOptions& o) {
  const std::vector<std::string> tasks = p.step_tasks();
  std::string list;
  for (const auto& t : tasks) list += (list.empty() ? "'" : ", '") + Printable(t) + "'";
  if (!o.trajectory_task.empty()) {
    if (std::find(tasks.begin(), tasks.end(), o.trajectory_task) == tasks.end())
      throw UsageError{
          "--trajectory-task: no propagate_by_preintegration task named '" +
          Printable(o.trajectory_task) + "'" +
          (tasks.empty() ? std::string(" (the pipeline has none)") : " (there are " + list + ")")};
    return o.trajectory_task;
  }
  if (tasks.empty())
    throw UsageError{
        "--tum and --errors write a propagate_by_preintegration task's steps; the pipeline has "
        "none"};
  if (tasks.size() > 1)
    throw UsageError{"the pipeline has several propagate_by_preintegration tasks (" + list +
                     "): name one with --trajectory-task"};
  return tasks.front();
}

/// The shortest text that reads back as x (as the JSON output writes numbers).
std::string Shortest(double x) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, x);
  return std::string(buf, r.ptr);
}

/// "seconds" for TUM: absolute (from the integer nanoseconds, exactly) when known.
std::string TumTime(const pipeline::StepOut& s) {
  char buf[64];
  if (s.t_end_abs_ns) {
    const std::int64_t ns = *s.t_end_abs_ns;
    std::snprintf(buf, sizeof buf, "%s%" PRId64 ".%09" PRId64, ns < 0 ? "-" : "",
                  (ns < 0 ? -ns : ns) / 1000000000, (ns < 0 ? -ns : ns) % 1000000000);
  } else {
    return Shortest(s.t_end.value_or(0.0));
  }
  return buf;
}

std::string TumLine(const pipeline::StepOut& s) {
  // Hamilton, body to world, as the JSON output's q_wxyz; TUM orders it qx qy qz qw.
  const Eigen::Vector4d q = so3::ToQuaternionWxyz(s.x_e.R);
  std::string line = TumTime(s);
  for (double v : {s.x_e.p.x(), s.x_e.p.y(), s.x_e.p.z(), q[1], q[2], q[3], q[0]})
    line += " " + Shortest(v);
  return line + "\n";
}

std::string ErrorsLine(const pipeline::StepOut& s) {
  return std::to_string(s.k) + "," + Shortest(s.t_end.value_or(0.0)) + "," +
         (s.t_end_abs_ns ? std::to_string(*s.t_end_abs_ns) : "") + "," +
         Shortest(*s.position_error_m) + "," + Shortest(*s.rotation_error_deg) + "," +
         (s.velocity_error_mps ? Shortest(*s.velocity_error_mps) : "") +
         "\n";  // empty: pose-only ground truth
}

bool EndsWithNpz(const std::string& path) {
  if (path.size() < 4) return false;
  std::string ext = path.substr(path.size() - 4);
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext == ".npz";
}

/// Whether the output is a terminal: stdout ("-" and its other names) or a path that is one.
bool IsTerminal(const pipeline::OutputFile& file) {
  if (file.is_stdout()) return isatty(STDOUT_FILENO) == 1;
  struct stat st {};
  if (stat(file.path().c_str(), &st) != 0 || !S_ISCHR(st.st_mode)) return false;
  const int fd = open(file.path().c_str(), O_WRONLY | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) return false;  // then the output's own open reports it
  const bool tty = isatty(fd) == 1;
  close(fd);
  return tty;
}

/// The result as NPZ: the arrays are collected from the values the tasks write (the document's
/// numbers are never formatted as text and read back), and the archive is written into `file`
/// (not committed).
void RunToNpz(const pipeline::Pipeline& p, const pipeline::RunOptions& ro,
              pipeline::OutputFile& file) {
  const pipeline::ResultArrays arrays =
      pipeline::RunToArrays(p, ro, [&] { file.refuse_if_loaded_object(); });
  pipeline::WriteResultNpz(arrays, [&](std::string_view s) { file.write(s); });
}

int ExecuteRun(const CommandContext& ctx, const RunCommandOptions& o) {
  const pipeline::Pipeline p = pipeline::Pipeline::Load(o.pipeline);
  std::optional<pipeline::RunOptions::Shard> shard;
  if (!o.shard.empty()) {
    const auto [index, count] = ParseShardOption(o.shard);
    shard = pipeline::RunOptions::Shard{index, count};
    if (!o.tum.empty() || !o.errors.empty())
      throw UsageError{
          "--shard: --tum and --errors are for a whole run (a shard may not hold the task)"};
  }
  std::string trajectory_task;
  if (!o.tum.empty() || !o.errors.empty())
    trajectory_task = TrajectoryTask(p, o);
  else if (!o.trajectory_task.empty())
    throw UsageError{"--trajectory-task is for --tum and --errors"};
  if (!o.errors.empty() && !p.has_ground_truth())
    throw UsageError{
        "--errors writes the steps' errors against the ground truth; the pipeline has no "
        "/ground_truth"};
  std::string out = o.output;
  // The pipeline's own "output" (perhaps someone else's pipeline) is confined to its directory,
  // links resolved (the parser's check is only lexical); -o, typed by the user, is not.
  std::optional<pipeline::OutputFile::Confinement> within;
  if (out.empty() && p.output_path()) {
    out = *p.output_path();
    const std::string dir = std::filesystem::path(p.file()).parent_path().string();
    within = pipeline::OutputFile::Confinement{dir.empty() ? "." : dir,
                                               Printable(p.file()) + ": /output"};
  }
  if (out.empty()) out = "-";
  // NPZ by --format, else by the destination's extension.
  if (!o.format.empty() && o.format != "json" && o.format != "npz")
    throw UsageError{"--format: expected json or npz, found '" + Printable(o.format) + "'"};
  const bool npz = o.format == "npz" || (o.format.empty() && EndsWithNpz(out));
  if (npz && shard)
    throw UsageError{"--shard writes JSON (imuconv merge joins the shards); not --format npz"};
  if (npz && o.output.empty() && !p.output_path())
    throw UsageError{
        "--format npz: give the output file with -o OUT.npz (-o - writes it to stdout, not a "
        "terminal)"};
  // The destination is examined before any work (nothing is created yet): what kind of file
  // it is, and that it is none of the files the run reads or loads.
  pipeline::OutputFile file(out, within);
  if (npz && IsTerminal(file))
    throw UsageError{"NPZ is binary: not written to a terminal (" + Printable(out) +
                     "); give a file with -o OUT.npz"};
  const std::vector<std::string> inputs = p.input_files();
  for (std::size_t i = 0; i < inputs.size(); ++i)
    file.refuse_if_same(inputs[i], inputs[i] == p.file() ? "the pipeline" : "the input file");
  // The trajectory files: examined like the output, before any work; none may be an input
  // or another output (compared as files: OutputFile::refuse_if_same_output).
  const std::string out_role = !o.output.empty() ? "-o"
                               : p.output_path() ? Printable(p.file()) + "'s /output"
                                                 : "standard output";
  std::optional<pipeline::OutputFile> tum, errors;
  for (auto [path, f, what] :
       {std::tuple{&o.tum, &tum, "--tum"}, std::tuple{&o.errors, &errors, "--errors"}}) {
    if (path->empty()) continue;
    f->emplace(*path);
    for (const auto& in : inputs)
      (*f)->refuse_if_same(in, in == p.file() ? "the pipeline" : "the input file");
    (*f)->refuse_if_same_output(what, file, out_role);
    if ((*f)->is_stdout())
      throw UsageError{std::string(what) +
                       ": give a file, not stdout (stdout carries the summary or the JSON output)"};
  }
  if (tum && errors) errors->refuse_if_same_output("--errors", *tum, "--tum");
  std::string tum_text, errors_text;
  if (errors)
    errors_text = "k,t_end,t_end_abs_ns,position_error_m,rotation_error_deg,velocity_error_mps\n";
  pipeline::RunOptions ro;
  std::vector<std::string> inconsistent;  // check tasks whose verdict is inconsistent
  ro.inconsistent_checks = &inconsistent;
  std::vector<std::string> unconverged;  // optimize tasks whose solve did not converge
  ro.unconverged_solves = &unconverged;
  ro.plugin_dirs = ctx.plugin_dirs();
  {
    std::vector<std::string> dirs = ro.plugin_dirs;
    dirs.insert(dirs.end(), p.plugin_dirs().begin(), p.plugin_dirs().end());
    PrintSearchPath(ctx, dirs);
  }
  ro.allow_plugin_override = ctx.allow_plugin_override;
  ro.log = &std::cerr;
  const bool quiet = o.quiet || ctx.quiet();
  ro.summary = quiet ? nullptr : (file.is_stdout() ? &std::cerr : &std::cout);
  ro.threads = o.threads;
  ro.shard = shard;
  ro.every_row = o.every_row;
  if (tum || errors)
    ro.on_step = [&](const pipeline::StepOut& s) {
      if (s.task != trajectory_task) return;
      if (tum) tum_text += TumLine(s);
      if (errors && s.position_error_m) errors_text += ErrorsLine(s);
    };
  // The runner loads the plugins and hands text to the sink only once the plugins, the data and
  // the times have been checked. Then, before a file's temporary is created, the destination
  // must not be a plugin (or library) the run has loaded. The text for a device, a FIFO or
  // stdout is held until the run has succeeded: a failing run writes nothing anywhere.
  if (npz) {
    RunToNpz(p, ro, file);
  } else {
    bool first = true;
    pipeline::RunToText(p, ro, [&](std::string_view s) {
      if (first) file.refuse_if_loaded_object();
      first = false;
      file.write(s);
    });
  }
  // Neither trajectory file may be the program or a plugin or library the run has loaded,
  // checked before anything is committed: a refusal then leaves no output behind.
  for (auto* f : {&tum, &errors})
    if (*f) (*f)->refuse_if_loaded_object();
  std::cout.flush();
  file.commit();
  for (auto [f, text] : {std::pair{&tum, &tum_text}, std::pair{&errors, &errors_text}}) {
    if (!*f) continue;
    (*f)->write(*text);
    (*f)->commit();
  }
  if (!quiet && !file.is_stdout()) std::cout << "\nwrote " << Printable(out) << "\n";
  // The document is complete and written; a check task that found an inconsistency makes the
  // run's exit code 1, as imuconv check's verdict does (exit_codes.h; 3 until the table was one).
  for (const auto& name : inconsistent)
    std::cerr << "imuconv: check task '" << Printable(name)
              << "': inconsistent (see its \"measurements\" in the output)\n";
  // A solve that stopped before converging is no answer: the run exits 1 as imuconv optimize
  // does, also under -q, which hides the summary line that says so.
  for (const auto& name : unconverged)
    std::cerr << "imuconv: optimize task '" << Printable(name)
              << "': the solve did not converge (see its \"solver\" in the output)\n";
  return inconsistent.empty() && unconverged.empty() ? kExitOk : kExitInconsistent;
}

// The command line of imuconv run: its description, and its flags onto the options.
void DeclareRunCommand(CLI::App* sub, RunCommandOptions* o) {
  sub->description(
      "Run a JSON pipeline (schemas/pipeline.schema.json). The result "
      "goes to -o, else to the pipeline's "
      "\"output\", else to stdout, as JSON or (--format npz, or an "
      "output named *.npz) as a NumPy .npz of its "
      "arrays (docs/interop.md); the summary goes to stdout (stderr "
      "when the result does). A failing run writes "
      "nothing.");
  sub->add_option("pipeline", o->pipeline, "Pipeline file")->required()->type_name("PIPELINE.json");
  AddOutputPathOption(
      *sub, "-o,--output", o->output,
      "Output file: a regular file is replaced atomically (keeping its permissions; a "
      "symbolic link is "
      "followed to it); a device or FIFO is written through; '-' is stdout. Never one "
      "of the inputs",
      "OUT.json|OUT.npz");
  sub->add_option("--format", o->format,
                  "json (the default) or npz: every array of the result in one NumPy .npz "
                  "(uncompressed; keys are "
                  "the JSON pointers with the indices of arrays of objects removed, values stacked "
                  "over them; a "
                  "JSON sidecar \"meta\" holds the rest; see docs/interop.md). An output named "
                  "*.npz means npz. "
                  "npz needs -o (or the pipeline's \"output\") and is never written to a terminal")
      ->type_name("FORMAT");
  sub->add_flag("-q,--quiet", o->quiet, "Do not print the summary");
  AddOutputPathOption(
      *sub, "--tum", o->tum,
      "Also write a propagate_by_preintegration task's predicted end states as a TUM trajectory "
      "(t x y z qx qy qz qw; t absolute seconds when the data's time origin is known), as evo "
      "reads it",
      "TRAJ.txt");
  AddOutputPathOption(
      *sub, "--errors", o->errors,
      "Also write that task's per-step errors against the ground truth as CSV "
      "(k, t_end, t_end_abs_ns, position_error_m, rotation_error_deg, velocity_error_mps)",
      "ERRORS.csv");
  sub->add_option("--trajectory-task", o->trajectory_task,
                  "The propagate_by_preintegration task --tum and --errors write (needed when "
                  "there are several)")
      ->type_name("NAME");
  sub->add_flag("--table", o->every_row,
                "Print every row of a step table (by default one of more than 50 steps shows its "
                "totals and worst steps)");
  sub->add_option("-j,--threads", o->threads,
                  "Threads for independent intervals (0 = every core, the default; 1 = serial). "
                  "The output is the "
                  "same, byte for byte, for any number")
      ->type_name("N");
  sub->add_option(
         "--shard", o->shard,
         "Run shard K of N (0 <= K < N): a contiguous block of the tasks (never splitting a task "
         "from an "
         "earlier one it names), written as the whole run's document with a first member \"shard\" "
         "and "
         "only the block's tasks; imuconv merge joins the N shards into the whole run's bytes "
         "(examples/batch/)")
      ->type_name("K/N");
}

}  // namespace

void RegisterRunCommand(CLI::App& app, CommandContext& ctx) {
  AddCommand(app, ctx, "run", DeclareRunCommand, ExecuteRun);
}

}  // namespace imuconv::cli
