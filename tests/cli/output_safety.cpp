// `imuconv run` never destroys what is not its own: a device or FIFO is
// written through, a symbolic link followed, a file's mode kept, a file with several hard links
// refused; an output that is one of the inputs is refused with the input left byte for byte; a
// pipeline's "output" stays inside its directory; an interrupted run leaves no temporary.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <map>
#include <string>
#include <thread>
#include <vector>

#include "../pipeline/pipeline_test_util.h"

extern char** environ;

namespace {
using namespace imuconv::test;
using nlohmann::json;

mode_t Lmode(const std::string& p) {
  struct stat st {};
  EXPECT_EQ(::lstat(p.c_str(), &st), 0) << p;
  return st.st_mode;
}

/// Copies examples/<name> and the data files it names into `tmp` (same layout), so that a
/// test that fails to refuse destroys only copies. Returns the pipeline's path in tmp.
std::string CopyExample(const TempDir& tmp, const std::string& name,
                        const std::vector<std::string>& data) {
  fs::create_directories(tmp.file("data"));
  for (const auto& d : data) fs::copy_file(SourcePath("examples/data/" + d), tmp.file("data/" + d));
  fs::copy_file(SourcePath("examples/" + name), tmp.file(name));
  return tmp.file(name);
}

std::string Generic(const TempDir& tmp) {
  return CopyExample(tmp, "generic_csv.json",
                     {"generic_imu_seconds.csv", "V1_01_easy_groundtruth_vicon2gt_slice.csv"});
}

/// Every file of a directory with its bytes, to show that nothing in it changed.
std::map<std::string, std::string> FilesWithBytes(const std::string& dir) {
  std::map<std::string, std::string> m;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file()) m[e.path().string()] = ReadText(e.path().string());
  return m;
}

TEST(OutputSafety, DevNullStaysACharacterDevice) {
  TempDir tmp;
  const std::string p = Generic(tmp);
  const CommandResult r = RunImuconv("run " + ShellQuote(p) + " -o /dev/null", tmp);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(Has(r.out, "wrote /dev/null")) << r.out;
  // As root a rename over /dev/null succeeds: this is what the old code did.
  EXPECT_TRUE(S_ISCHR(Lmode("/dev/null")));
}

TEST(OutputSafety, FifoIsWrittenThrough) {
  TempDir tmp;
  const std::string p = Generic(tmp);
  const std::string fifo = tmp.file("results.fifo");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  std::string received;
  std::thread reader([&] { received = ReadText(fifo); });  // opens, blocking until imuconv does
  const CommandResult r =
      RunImuconv("run " + ShellQuote(p) + " -o " + ShellQuote(fifo) + " -q", tmp);
  // Whatever happened, let the reader finish (ENXIO when it already has).
  const int fd = ::open(fifo.c_str(), O_WRONLY | O_NONBLOCK);
  if (fd >= 0) ::close(fd);
  reader.join();
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(S_ISFIFO(Lmode(fifo)));
  const json doc = json::parse(received, nullptr, false);
  ASSERT_FALSE(doc.is_discarded()) << received.substr(0, 200);
  EXPECT_EQ(doc["tasks"].size(), 4u);
}

TEST(OutputSafety, StdoutByNameGetsTheDocumentAndTheSummaryGoesToStderr) {
  TempDir tmp;
  const std::string p = Generic(tmp);
  for (const char* out : {"-", "/dev/stdout", "/dev/fd/1"}) {
    const CommandResult r = RunImuconv("run " + ShellQuote(p) + " -o " + out, tmp);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    const json doc = json::parse(r.out, nullptr, false);
    ASSERT_FALSE(doc.is_discarded()) << out << ": stdout is not one JSON document:\n"
                                     << r.out.substr(0, 300);
    EXPECT_EQ(doc["tasks"].size(), 4u);
    EXPECT_TRUE(Has(r.err, "residual 'residuals_vs_gt'"))
        << out << ": the summary belongs on stderr\n"
        << r.err;
  }
  EXPECT_EQ(tmp.entries(), 2u);  // the pipeline and data/
}

TEST(OutputSafety, SymbolicLinkIsFollowedAndStaysALink) {
  TempDir tmp;
  const std::string p = Generic(tmp);
  fs::create_directories(tmp.file("results"));
  const std::string target = tmp.write("results/run.json", "old\n");
  fs::create_symlink("results/run.json", tmp.file("latest.json"));
  const CommandResult r = RunImuconv(
      "run " + ShellQuote(p) + " -o " + ShellQuote(tmp.file("latest.json")) + " -q", tmp);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(S_ISLNK(Lmode(tmp.file("latest.json"))));
  EXPECT_EQ(json::parse(ReadText(target))["tasks"].size(), 4u);
  EXPECT_EQ(std::distance(fs::directory_iterator(tmp.file("results")), fs::directory_iterator()),
            1);
}

TEST(OutputSafety, ModeIsKept) {
  TempDir tmp;
  const std::string p = Generic(tmp);
  const std::string out = tmp.write("private.json", "old\n");
  ASSERT_EQ(::chmod(out.c_str(), 0600), 0);
  const CommandResult r =
      RunImuconv("run " + ShellQuote(p) + " -o " + ShellQuote(out) + " -q", tmp);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(Lmode(out) & 07777, 0600u);
  EXPECT_EQ(json::parse(ReadText(out))["tasks"].size(), 4u);
}

TEST(OutputSafety, FileWithSeveralHardLinksIsRefused) {
  TempDir tmp;
  const std::string p = Generic(tmp);
  const std::string out = tmp.write("result.json", "shared\n");
  ASSERT_EQ(::link(out.c_str(), tmp.file("backup.json").c_str()), 0);
  const CommandResult r =
      RunImuconv("run " + ShellQuote(p) + " -o " + ShellQuote(out) + " -q", tmp);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(
      Has(r.err, "imuconv: error: " + out + ": has 2 hard links; replacing it would split them"))
      << r.err;
  EXPECT_EQ(ReadText(out), "shared\n");
  EXPECT_EQ(ReadText(tmp.file("backup.json")), "shared\n");
}

TEST(OutputSafety, AnInputIsNeverTheOutput) {
  TempDir tmp;
  const std::string p = Generic(tmp);
  const std::string imu = tmp.file("data/generic_imu_seconds.csv");
  const std::string gt = tmp.file("data/V1_01_easy_groundtruth_vicon2gt_slice.csv");
  fs::create_symlink("data/generic_imu_seconds.csv", tmp.file("imu_link.json"));
  const auto before = FilesWithBytes(tmp.path());
  const std::vector<std::pair<std::string, std::string>> cases = {
      {p, "is the same file as the pipeline " + p},
      {imu, "is the same file as the input file " + imu},
      {gt, "is the same file as the input file " + gt},
      {tmp.file("imu_link.json"), "is the same file as the input file " + imu},
      {tmp.file("data/../data/generic_imu_seconds.csv"),
       "is the same file as the input file " + imu},
  };
  for (const auto& [out, says] : cases) {
    const CommandResult r = RunImuconv("run " + ShellQuote(p) + " -o " + ShellQuote(out), tmp);
    EXPECT_EQ(r.exit_code, 2) << out;
    EXPECT_TRUE(Has(r.err, "imuconv: error: " + out + ": " + says + ": refusing to overwrite it"))
        << r.err;
    EXPECT_EQ(r.out, "") << "refused before the run";
  }
  EXPECT_TRUE(FilesWithBytes(tmp.path()) == before) << "an input changed";
  EXPECT_TRUE(S_ISLNK(Lmode(tmp.file("imu_link.json"))));
  EXPECT_EQ(tmp.entries(), 3u);  // no temporaries
}

TEST(OutputSafety, AMeasurementsFileIsNeverTheOutput) {
  TempDir tmp;
  const std::string p =
      CopyExample(tmp, "gtsam_import.json", {"gtsam_smooth0_manifold.measurements.json"});
  const std::string meas = tmp.file("data/gtsam_smooth0_manifold.measurements.json");
  const auto before = FilesWithBytes(tmp.path());
  CommandResult r = RunImuconv("run " + ShellQuote(p) + " -o " + ShellQuote(meas), tmp);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Has(
      r.err, meas + ": is the same file as the input file " + meas + ": refusing to overwrite it"))
      << r.err;
  EXPECT_TRUE(FilesWithBytes(tmp.path()) == before);
  // The same through the pipeline's own "output" key.
  json doc = json::parse(ReadText(p));
  doc["output"] = "data/gtsam_smooth0_manifold.measurements.json";
  const std::string p2 = tmp.write("self.json", doc.dump());
  r = RunImuconv("run " + ShellQuote(p2), tmp);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Has(r.err, "is the same file as the input file")) << r.err;
  EXPECT_EQ(ReadText(meas), before.at(meas));
  // Sanity: the pipeline does run, to a fresh file.
  r = RunImuconv("run " + ShellQuote(p) + " -o " + ShellQuote(tmp.file("fresh.json")) + " -q", tmp);
  EXPECT_EQ(r.exit_code, 0) << r.err;
}

TEST(OutputSafety, PipelineOutputKeyStaysInsideItsDirectory) {
  TempDir tmp;
  const std::string p = Generic(tmp);
  // The pipeline one level down, so that an escape it was allowed would still land in tmp.
  fs::create_directories(tmp.file("inner"));
  json doc = json::parse(ReadText(p));
  doc["imu"]["path"] = "../data/generic_imu_seconds.csv";
  doc["ground_truth"]["path"] = "../data/V1_01_easy_groundtruth_vicon2gt_slice.csv";
  for (const std::string& bad : std::vector<std::string>{
           "../elsewhere.json", "sub/../../elsewhere.json", tmp.file("absolute.json"), ".."}) {
    doc["output"] = bad;
    const std::string pipe = tmp.write("inner/escape.json", doc.dump());
    const CommandResult r = RunImuconv("run " + ShellQuote(pipe), tmp);
    EXPECT_EQ(r.exit_code, 2) << bad;
    EXPECT_TRUE(
        Has(r.err, pipe + ": /output: expected a relative path inside the pipeline's directory"))
        << r.err;
    EXPECT_TRUE(Has(r.err, "-o")) << r.err;
  }
  EXPECT_FALSE(fs::exists(tmp.file("elsewhere.json")));
  EXPECT_FALSE(fs::exists(tmp.file("absolute.json")));
  // Inside it (after normalisation) is fine; -o, typed by the user, is not restricted.
  doc["output"] = "sub/../inside.json";
  const std::string ok = tmp.write("inner/inside.pipeline.json", doc.dump());
  CommandResult r = RunImuconv("run " + ShellQuote(ok) + " -q", tmp);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(json::parse(ReadText(tmp.file("inner/inside.json")))["tasks"].size(), 4u);
  fs::create_directories(tmp.file("a/b"));
  r = RunImuconv(
      "run " + ShellQuote(ok) + " -q -o " + ShellQuote(tmp.file("a/b/../outside_by_o.json")), tmp);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(tmp.file("a/outside_by_o.json")));
}

/// Starts imuconv with `args` (no shell), stdout and stderr to /dev/null; returns its pid.
pid_t Spawn(const std::vector<std::string>& args) {
  std::vector<std::string> all = {Binary()};
  all.insert(all.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& a : all) argv.push_back(a.data());
  argv.push_back(nullptr);
  std::vector<std::string> env_store;
  for (char** e = environ; *e; ++e)
    if (std::string(*e).rfind("IMUCONV_PLUGIN_PATH=", 0) != 0) env_store.emplace_back(*e);
  std::vector<char*> envp;
  for (auto& e : env_store) envp.push_back(e.data());
  envp.push_back(nullptr);
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addopen(&fa, 1, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(&fa, 2, "/dev/null", O_WRONLY, 0);
  pid_t pid = -1;
  const int rc = posix_spawn(&pid, argv[0], &fa, nullptr, argv.data(), envp.data());
  posix_spawn_file_actions_destroy(&fa);
  return rc == 0 ? pid : -1;
}

std::vector<std::string> TemporariesIn(const std::string& dir) {
  std::vector<std::string> t;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().filename().string().find(".tmp.") != std::string::npos)
      t.push_back(e.path().string());
  return t;
}

TEST(OutputSafety, SigtermRemovesTheTemporaryAndKeepsTheOldOutput) {
  TempDir tmp;
  // Slow enough to be interrupted on any machine: the first task writes over 1 MiB (so the
  // runner hands text to the output and the temporary appears within a fraction of a second),
  // then 300 RK4 propagations over the whole 144 s EuRoC file follow, serially (about 7 s on
  // an idle 2024 machine; the test needs only the first second). Data read from the source
  // tree, by absolute path.
  json doc = json::parse(ReadText(SourcePath("examples/euroc_v1_01_full.json")));
  doc["imu"]["path"] = SourcePath("examples/data/V1_01_easy_imu0.csv");
  doc["ground_truth"]["path"] = SourcePath("examples/data/V1_01_easy_groundtruth_vicon2gt.csv");
  json tasks = json::array();
  tasks.push_back({{"type", "preintegrate"},
                   {"name", "kf"},
                   {"method", {{"propagator", "rk4"}}},
                   {"conventions", {"gtsam_manifold"}},
                   {"bias", "ground_truth"},
                   {"keyframes", {{"start", 0.0}, {"end", 20.0}, {"step", 0.1}}}});
  for (int i = 0; i < 300; ++i)
    tasks.push_back({{"type", "propagate"},
                     {"name", "p" + std::to_string(i)},
                     {"propagator", "rk4"},
                     {"state_convention", "left"},
                     {"start", {{"state", "ground_truth"}}},
                     {"interval", {{"t_start", 0.0}, {"t_end", 144.0}}}});
  doc["tasks"] = tasks;
  const std::string pipe = tmp.write("slow.json", doc.dump());
  const std::string out = tmp.write("result.json", "previous result\n");

  const pid_t pid = Spawn({"run", pipe, "-o", out, "-q", "-j", "1"});
  ASSERT_GT(pid, 0);
  bool seen = false, exited = false;
  int status = 0;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (std::chrono::steady_clock::now() < deadline) {
    if (!TemporariesIn(tmp.path()).empty()) {
      seen = true;
      break;
    }
    if (::waitpid(pid, &status, WNOHANG) == pid) {
      exited = true;
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  if (!seen && !exited) {
    ::kill(pid, SIGKILL);
    ::waitpid(pid, &status, 0);
    FAIL() << "no temporary appeared within 60 s";
  }
  if (exited)
    GTEST_SKIP() << "the run finished (status " << status << ") before its temporary was seen";
  ASSERT_EQ(::kill(pid, SIGTERM), 0);
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  if (WIFEXITED(status))
    GTEST_SKIP() << "the run finished (exit " << WEXITSTATUS(status) << ") before SIGTERM arrived";
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGTERM) << "status " << status;
  EXPECT_TRUE(TemporariesIn(tmp.path()).empty()) << TemporariesIn(tmp.path()).front();
  EXPECT_EQ(ReadText(out), "previous result\n");
  EXPECT_EQ(tmp.entries(), 2u);
}

}  // namespace
