// Issue 22, "Inputs are never written", through the command line (docs/outputs.md):
//   - every file a command reads, also one named inside another file (a pipeline's IMU CSV,
//     ground truth, Kalibr yaml; a measurements file), is an input no output may replace,
//     whatever name reaches it (a link elsewhere, /dev/fd/N);
//   - a pipeline's own "output" stays inside its directory with every link resolved;
//   - a closed standard descriptor is never reused for a file the tool opens;
//   - an empty output path is refused, naming the flag;
//   - a replaced output keeps its whole mode and its extended attributes.
// Each test fails on 33f3aef (the output written over the input with exit 0, the document
// outside, the summary inside the JSON, stdout used, the mode's high bits and xattrs lost).
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/xattr.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <map>
#include <string>
#include <vector>

#include "../pipeline/pipeline_test_util.h"
#include "gtsam_measurement.h"
#include "imuconv_test.h"
#include "number_text.h"

namespace {
using namespace imuconv::test;
using nlohmann::json;

/// Every regular file under `dir` with its bytes: nothing of it may change.
std::map<std::string, std::string> Snapshot(const std::string& dir) {
  std::map<std::string, std::string> m;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file() && e.path().filename().string()[0] != '.')
      m[e.path().string()] = ReadText(e.path().string());
  return m;
}

/// Names of temporaries (".NAME.tmp.XXXX") left anywhere under `dir`.
std::vector<std::string> Temporaries(const std::string& dir) {
  std::vector<std::string> t;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (Has(e.path().filename().string(), ".tmp.")) t.push_back(e.path().string());
  return t;
}

/// The files under a test's directory as they were when it was constructed: after the refused
/// commands, none may have changed and no temporary may be left behind.
class Unchanged {
 public:
  explicit Unchanged(const TempDir& tmp) : tmp_(tmp), before_(Snapshot(tmp.path())) {}
  void Expect() const {
    EXPECT_TRUE(Snapshot(tmp_.path()) == before_) << "an input changed";
    EXPECT_TRUE(Temporaries(tmp_.path()).empty());
  }

 private:
  const TempDir& tmp_;
  std::map<std::string, std::string> before_;
};

/// A symbolic link at `link` (relative to tmp; its directory made) to `target`; its path.
std::string LinkIn(const TempDir& tmp, const std::string& link, const std::string& target) {
  fs::create_directories(fs::path(tmp.file(link)).parent_path());
  fs::create_symlink(target, tmp.file(link));
  return tmp.file(link);
}

/// The imuconv command line `command` with --report `report`.
CommandResult WithReport(const std::string& command, const std::string& report,
                         const TempDir& tmp) {
  return RunImuconv(command + " --report " + ShellQuote(report), tmp);
}

/// Runs `command` (a shell command line; the binary is $IMUCONV) in `dir`, with the
/// redirections it gives itself; stderr to dir/.err unless the command says otherwise.
CommandResult Shell(const std::string& command, const TempDir& tmp) {
  const std::string cmd = "cd " + ShellQuote(tmp.path()) +
                          " && env -u IMUCONV_PLUGIN_PATH IMUCONV=" + ShellQuote(Binary()) +
                          " sh -c " + ShellQuote(command);
  const int status = std::system(cmd.c_str());
  CommandResult r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  if (fs::exists(tmp.file(".err"))) {
    r.err = ReadText(tmp.file(".err"));
    fs::remove(tmp.file(".err"));
  }
  return r;
}

/// examples/euroc_v1_01_keyframes.json with its data copied into tmp, its noise read from a
/// Kalibr imu.yaml (tests/data/kalibr) beside it: three files named inside the pipeline.
struct Euroc {
  std::string pipeline, imu, gt, kalibr;
};
Euroc CopyEuroc(const TempDir& tmp) {
  fs::create_directories(tmp.file("data"));
  Euroc e;
  e.imu = tmp.file("data/V1_01_easy_imu0_slice.csv");
  e.gt = tmp.file("data/V1_01_easy_groundtruth_vicon2gt_slice.csv");
  e.kalibr = tmp.file("data/imu.yaml");
  fs::copy_file(SourcePath("examples/data/V1_01_easy_imu0_slice.csv"), e.imu);
  fs::copy_file(SourcePath("examples/data/V1_01_easy_groundtruth_vicon2gt_slice.csv"), e.gt);
  fs::copy_file(DataPath("kalibr/euroc_imu.yaml"), e.kalibr);
  json doc = ReadJson(SourcePath("examples/euroc_v1_01_keyframes.json"));
  doc.erase("$schema");
  doc["noise"] = {{"kalibr", "data/imu.yaml"}};
  e.pipeline = tmp.write("euroc.json", doc.dump(1));
  return e;
}

// ---- an output is never an input ------------------------------------------------------------

TEST(InputsNeverWritten, NeesReportNamingAFileThePipelineNamesIsRefused) {
  TempDir tmp;
  const Euroc e = CopyEuroc(tmp);
  // another directory, another name
  const std::string elsewhere = LinkIn(tmp, "elsewhere/report.html", e.kalibr);
  const Unchanged inputs(tmp);
  const std::string nees =
      "-q nees --pipeline " + ShellQuote(e.pipeline) + " --windows 0.5 --method rk4";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {e.imu, e.imu},
      {e.gt, e.gt},
      {e.kalibr, e.kalibr},
      {elsewhere, e.kalibr},
  };
  for (const auto& [report, input] : cases) {
    const CommandResult r = WithReport(nees, report, tmp);
    EXPECT_EQ(r.exit_code, 2) << report << "\n" << r.err;  // nees: 2 = no result
    EXPECT_TRUE(Has(r.err, "is the same file as the input file")) << r.err;
    EXPECT_TRUE(Has(r.err, fs::path(input).filename().string() + ": refusing to overwrite it"))
        << r.err;
  }
  // /dev/fd/3 opened read-write on the IMU CSV by the shell: written through, it would land on
  // the samples at offset 0. The descriptor's file is the input, whatever its name.
  const CommandResult r = Shell("\"$IMUCONV\" " + nees + " --report /dev/fd/3 3<>" +
                                    ShellQuote(e.imu) + " > /dev/null 2> .err",
                                tmp);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_TRUE(Has(r.err, "/dev/fd/3: is the same file as the input file")) << r.err;
  inputs.Expect();
  // Sanity: the same command writes a report elsewhere.
  const CommandResult ok = WithReport(nees, tmp.file("report.html"), tmp);
  EXPECT_EQ(ok.exit_code, 0) << ok.err;
  EXPECT_TRUE(Has(ReadText(tmp.file("report.html")), "<html")) << "a report was written";
}

/// The smooth-0 reference case as a pipeline over a generic CSV, with GTSAM's measurement of
/// it to check (as tests/cli/check_pipeline.cpp builds them).
struct CheckFiles {
  std::string pipeline, csv, meas;
};
CheckFiles CheckInputs(const TempDir& tmp) {
  const json c = ReadJson(DataPath("reference/cases/smooth-0.json"));
  const json m = GtsamMeasurement("smooth-0");
  CheckFiles f;
  f.meas = tmp.write("smooth.meas.json", json{{"measurements", json::array({m})}}.dump());
  std::string csv = "t;wx;wy;wz;ax;ay;az\n";
  for (const auto& row : c["imu"]) {
    for (int k = 0; k < 7; ++k) csv += (k ? ";" : "") + Num17(row[k].get<double>());
    csv += "\n";
  }
  f.csv = tmp.write("smooth.csv", csv);
  const json p = {
      {"noise", c["noise"]},
      {"imu", CsvImuFromTimeZero(f.csv, "s", "t", ";")},
      {"tasks",
       json::array({{{"type", "check"}, {"name", "chk"}, {"measurements", {{"file", f.meas}}}}})}};
  f.pipeline = tmp.write("smooth.pipeline.json", p.dump(1));
  return f;
}

TEST(InputsNeverWritten, CheckReportNamingThePipelinesSamplesIsRefused) {
  TempDir tmp;
  const CheckFiles f = CheckInputs(tmp);
  const std::string link = LinkIn(tmp, "links/samples.html", f.csv);
  const Unchanged inputs(tmp);
  const std::string check =
      "-q check " + ShellQuote(f.meas) + " --pipeline " + ShellQuote(f.pipeline);
  for (const std::string& report : {f.csv, link}) {
    const CommandResult r = WithReport(check, report, tmp);
    EXPECT_EQ(r.exit_code, 2) << report << "\n" << r.err;  // check: 2 = nothing could be checked
    EXPECT_TRUE(
        Has(r.err, "is the same file as the input file " + f.csv + ": refusing to overwrite it"))
        << r.err;
  }
  inputs.Expect();
  const CommandResult ok = WithReport(check, tmp.file("r.html"), tmp);
  EXPECT_EQ(ok.exit_code, 0) << ok.err;  // GTSAM's own numbers are consistent
  EXPECT_TRUE(fs::exists(tmp.file("r.html")));
}

// ---- a pipeline's "output" stays inside its directory ------------------------------------

TEST(InputsNeverWritten, PipelineOutputKeyCannotLeaveThroughALink) {
  TempDir tmp;
  fs::create_directories(tmp.file("inner/data"));
  fs::create_directories(tmp.file("outside"));
  for (const char* d : {"generic_imu_seconds.csv", "V1_01_easy_groundtruth_vicon2gt_slice.csv"})
    fs::copy_file(SourcePath(std::string("examples/data/") + d),
                  tmp.file(std::string("inner/data/") + d));
  json doc = ReadJson(SourcePath("examples/generic_csv.json"));
  doc.erase("$schema");
  const std::string victim = tmp.write("outside/victim.txt", "not yours\n");
  fs::create_symlink("../outside/victim.txt", tmp.file("inner/out.json"));  // the example
  fs::create_symlink("../outside", tmp.file("inner/sub"));                  // a linked directory
  fs::create_symlink("hop.json", tmp.file("inner/chain.json"));             // inside, then out
  fs::create_symlink(victim, tmp.file("inner/hop.json"));
  fs::create_symlink("/dev/fd/1", tmp.file("inner/fd.json"));  // our stdout
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"out.json", "leads outside the pipeline's directory"},
      {"sub/victim.txt", "leads outside the pipeline's directory"},
      {"sub/new.json", "leads outside the pipeline's directory"},
      {"chain.json", "leads outside the pipeline's directory"},
      {"fd.json", "leads to file descriptor 1 of this process, outside the pipeline's directory"},
  };
  for (const auto& [output, says] : cases) {
    doc["output"] = output;
    const std::string p = tmp.write("inner/p.json", doc.dump());
    const CommandResult r = RunImuconv("run " + ShellQuote(p) + " -q", tmp);
    EXPECT_EQ(r.exit_code, 2) << output << "\n" << r.err;
    EXPECT_TRUE(Has(r.err, p + ": /output: ")) << r.err;
    EXPECT_TRUE(Has(r.err, says)) << r.err;
    EXPECT_TRUE(Has(r.err, "-o")) << r.err;
    EXPECT_EQ(r.out, "") << output;
  }
  EXPECT_EQ(ReadText(victim), "not yours\n");
  EXPECT_FALSE(fs::exists(tmp.file("outside/new.json")));
  EXPECT_TRUE(Temporaries(tmp.path()).empty());
  // A link that stays inside is followed (and stays a link).
  LinkIn(tmp, "inner/latest.json", tmp.file("inner/results/real.json"));
  fs::create_directories(tmp.file("inner/results"));
  doc["output"] = "latest.json";
  const std::string p = tmp.write("inner/p.json", doc.dump());
  const CommandResult r = RunImuconv("run " + ShellQuote(p) + " -q", tmp);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::is_symlink(tmp.file("inner/latest.json")));
  EXPECT_EQ(json::parse(ReadText(tmp.file("inner/results/real.json")))["tasks"].size(), 4u);
}

// ---- closed standard descriptors -------------------------------------------------------------

std::string CopyGeneric(const TempDir& tmp) {
  fs::create_directories(tmp.file("data"));
  for (const char* d : {"generic_imu_seconds.csv", "V1_01_easy_groundtruth_vicon2gt_slice.csv"})
    fs::copy_file(SourcePath(std::string("examples/data/") + d),
                  tmp.file(std::string("data/") + d));
  json doc = ReadJson(SourcePath("examples/generic_csv.json"));
  doc.erase("$schema");
  return tmp.write("generic.json", doc.dump(1));
}

TEST(InputsNeverWritten, ClosedStandardOutputIsNeverAFileOfOurs) {
  TempDir tmp;
  const std::string p = CopyGeneric(tmp);
  // The example: the summary, printed to descriptor 1, must not land in the document.
  CommandResult r = Shell("\"$IMUCONV\" run generic.json -o out.json >&- 2> .err", tmp);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  const std::string doc = ReadText(tmp.file("out.json"));
  EXPECT_FALSE(Has(doc, "wrote")) << "the summary is inside the document";
  EXPECT_EQ(json::parse(doc)["tasks"].size(), 4u);
  // Standard input and output closed, two outputs (the document and a TUM trajectory): each
  // file is only its own text.
  r = Shell("\"$IMUCONV\" run generic.json -o out2.json --tum traj.txt <&- >&- 2> .err", tmp);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(json::parse(ReadText(tmp.file("out2.json")))["tasks"].size(), 4u);
  const std::string traj = ReadText(tmp.file("traj.txt"));
  EXPECT_FALSE(traj.empty());
  EXPECT_FALSE(Has(traj, "{") || Has(traj, "wrote")) << traj.substr(0, 200);
  // "-o -" with standard output closed: refused, not written into /dev/null in silence.
  r = Shell("\"$IMUCONV\" run generic.json -o - >&- 2> .err", tmp);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_TRUE(Has(r.err, "-: standard output was closed when imuconv started")) << r.err;
}

// ---- the running program ---------------------------------------------------------------------

// An output naming the program that runs, as /proc/self/exe or by its own path, is refused and
// the program kept; a refused --tum leaves no document behind either. Before, -o /proc/self/exe
// replaced the binary with the document, exit 0 (and through the Python module, the
// interpreter), and --tum /proc/self/exe was refused only after -o's document was written.
TEST(InputsNeverWritten, TheRunningProgramIsNeverAnOutput) {
  TempDir tmp;
  CopyGeneric(tmp);
  const std::string program = tmp.file("imuconv_copy");
  fs::copy_file(Binary(), program);
  fs::permissions(program, fs::perms::owner_exec, fs::perm_options::add);
  const std::string bytes = ReadText(program);
  for (const char* outputs :
       {"-o /proc/self/exe", "-o ./imuconv_copy", "-o out.json --tum /proc/self/exe"}) {
    SCOPED_TRACE(outputs);
    const CommandResult r =
        Shell(std::string("./imuconv_copy -q run generic.json ") + outputs + " 2> .err", tmp);
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_TRUE(Has(r.err, "is the same file as the running program")) << r.err;
    EXPECT_FALSE(fs::exists(tmp.file("out.json")));
  }
  EXPECT_TRUE(ReadText(program) == bytes) << "the program was replaced";
}

// ---- an empty output path --------------------------------------------------------------------

TEST(InputsNeverWritten, EmptyOutputPathIsRefusedNamingTheFlag) {
  TempDir tmp;
  const std::string p = CopyGeneric(tmp);
  const std::string c = ShellQuote(DataPath("reference/cases/smooth-0.json"));
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"run " + ShellQuote(p) + " -o ''", "--output"},
      {"run " + ShellQuote(p) + " -o out.json --tum ''", "--tum"},
      {"run " + ShellQuote(p) + " -o out.json --errors ''", "--errors"},
      {"merge -o '' " + ShellQuote(p), "--output"},
      {"refcase " + c + " -o ''", "--output"},
      {"check " + ShellQuote(p) + " --case " + c + " --report ''", "--report"},
      {"montecarlo --case " + c + " --method rk4 --trials 20 --seed 1 --report ''", "--report"},
      {"montecarlo --case " + c + " --method rk4 --trials 20 --seed 1 --shard 0/2 -o ''",
       "--output"},
      {"nees --pipeline " + ShellQuote(p) + " --windows 0.5 --method rk4 --report ''", "--report"},
      {"experiment both --report ''", "--report"},
  };
  for (const auto& [args, flag] : cases) {
    const CommandResult r = RunImuconv(args, tmp);
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.err;
    EXPECT_TRUE(Has(r.err, flag + ": the output path is empty")) << args << "\n" << r.err;
    EXPECT_EQ(r.out, "") << args << ": nothing written to stdout";
  }
  EXPECT_FALSE(fs::exists(tmp.file("out.json")));
}

// ---- what a replaced output keeps -----------------------------------------------------------

TEST(InputsNeverWritten, ReplacedOutputKeepsItsWholeModeAndExtendedAttributes) {
  TempDir tmp;
  const std::string p = CopyGeneric(tmp);
  const std::string out = tmp.write("out.json", "old\n");
  // set-group-ID and sticky (the issue's), and set-user-ID: chmod keeps them for the owner in
  // their own group, which we are.
  for (mode_t mode : {mode_t{03640}, mode_t{04750}}) {
    ASSERT_EQ(::chmod(out.c_str(), mode), 0);
    struct stat st {};
    ASSERT_EQ(::stat(out.c_str(), &st), 0);
    if ((st.st_mode & 07777) != mode)
      GTEST_SKIP() << "this file system does not keep mode " << std::oct << mode;
    const CommandResult r =
        RunImuconv("run " + ShellQuote(p) + " -o " + ShellQuote(out) + " -q", tmp);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    ASSERT_EQ(::stat(out.c_str(), &st), 0);
    EXPECT_EQ(st.st_mode & 07777, mode) << std::oct << (st.st_mode & 07777);
    EXPECT_EQ(json::parse(ReadText(out))["tasks"].size(), 4u);
  }
  // Extended attributes: a user.* one (anyone's), and one whose value is binary with a NUL.
  const std::string binary("a\0b", 3);
  if (::setxattr(out.c_str(), "user.imuconv.origin", "lab-3", 5, 0) != 0)
    GTEST_SKIP() << "no user.* extended attributes on this file system: " << std::strerror(errno);
  ASSERT_EQ(::setxattr(out.c_str(), "user.imuconv.blob", binary.data(), binary.size(), 0), 0);
  const CommandResult r =
      RunImuconv("run " + ShellQuote(p) + " -o " + ShellQuote(out) + " -q", tmp);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_FALSE(Has(r.err, "warning")) << r.err;
  char buf[16] = {};
  ASSERT_EQ(::getxattr(out.c_str(), "user.imuconv.origin", buf, sizeof buf), 5)
      << std::strerror(errno);
  EXPECT_EQ(std::string(buf, 5), "lab-3");
  ASSERT_EQ(::getxattr(out.c_str(), "user.imuconv.blob", buf, sizeof buf), 3);
  EXPECT_EQ(std::string(buf, 3), binary);
  EXPECT_EQ(json::parse(ReadText(out))["tasks"].size(), 4u);
}

}  // namespace
