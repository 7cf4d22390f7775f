// Output files (OutputFile, apps/pipeline/include/imuconv/pipeline/output_file.h): a regular
// file is replaced atomically (a temporary in the same directory, renamed over it), keeping its
// mode; a symbolic link is followed to its target; a device or FIFO is written through, never
// replaced; anything else, and a file with several hard links, is refused. A failing run leaves
// no output (and an existing file untouched), and no temporaries.
#include <dlfcn.h>
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstring>
#include <thread>

#include "imuconv/pipeline/json_io.h"
#include "imuconv/pipeline/output_file.h"
#include "pipeline_test_util.h"

namespace {
using namespace imuconv::test;
using imuconv::pipeline::OutputFile;
using imuconv::pipeline::WriteFileAtomically;

mode_t Lmode(const std::string& p) {
  struct stat st {};
  EXPECT_EQ(::lstat(p.c_str(), &st), 0) << p;
  return st.st_mode;
}

/// The state letter of one of our threads (R running, S sleeping, ...), from /proc.
char ThreadState(pid_t tid) {
  const std::string stat = ReadText("/proc/self/task/" + std::to_string(tid) + "/stat");
  const auto paren = stat.rfind(')');
  return paren == std::string::npos || paren + 2 >= stat.size() ? '?' : stat[paren + 2];
}

/// Sets the umask for one scope (it is per process; each test binary runs its tests in turn).
struct Umask {
  explicit Umask(mode_t m) : old(::umask(m)) {}
  ~Umask() { ::umask(old); }
  mode_t old;
};

TEST(AtomicWrite, WritesReplacesAndLeavesNoTemporaries) {
  TempDir tmp;
  const std::string f = tmp.file("out.json");
  WriteFileAtomically(f, "{\"a\": 1}\n");
  EXPECT_EQ(ReadText(f), "{\"a\": 1}\n");
  WriteFileAtomically(f, "{\"a\": 2}\n");
  EXPECT_EQ(ReadText(f), "{\"a\": 2}\n");
  EXPECT_EQ(tmp.entries(), 1u);
}

TEST(AtomicWrite, MissingDirectoryThrowsAndWritesNothing) {
  TempDir tmp;
  const std::string f = tmp.file("no/such/dir/out.json");
  const std::string msg = MessageOf<imuconv::Error>([&] { WriteFileAtomically(f, "x"); });
  EXPECT_NE(msg.find(f + ": cannot create a temporary file in"), std::string::npos) << msg;
  EXPECT_EQ(tmp.entries(), 0u);
}

TEST(AtomicWrite, TemporaryOnlyFromTheFirstWriteAndRemovedWithoutCommit) {
  TempDir tmp;
  const std::string f = tmp.write("out.json", "previous\n");
  {
    OutputFile out(f);
    EXPECT_EQ(out.mode(), OutputFile::Mode::Replace);
    EXPECT_EQ(tmp.entries(), 1u) << "nothing may be created before the first write";
    out.write("partial");
    EXPECT_EQ(tmp.entries(), 2u) << "the temporary, next to the output";
    for (const auto& e : fs::directory_iterator(tmp.path()))
      if (e.path().filename() != "out.json") {
        EXPECT_EQ(e.path().filename().string().rfind(".out.json.tmp.", 0), 0u) << e.path();
      }
  }  // destroyed without commit(): a failure
  EXPECT_EQ(tmp.entries(), 1u);
  EXPECT_EQ(ReadText(f), "previous\n");
}

TEST(AtomicWrite, KeepsTheModeOfAFileItReplaces) {
  TempDir tmp;
  const Umask mask(022);
  const std::string secret = tmp.write("secret.json", "old\n");
  ASSERT_EQ(::chmod(secret.c_str(), 0600), 0);
  WriteFileAtomically(secret, "new\n");
  EXPECT_EQ(ReadText(secret), "new\n");
  EXPECT_EQ(Lmode(secret) & 07777, 0600u);
  const std::string open = tmp.write("open.json", "old\n");
  ASSERT_EQ(::chmod(open.c_str(), 0664), 0);
  WriteFileAtomically(open, "new\n");
  EXPECT_EQ(Lmode(open) & 07777, 0664u);
  // A new file: 0666 less the umask.
  WriteFileAtomically(tmp.file("fresh.json"), "x");
  EXPECT_EQ(Lmode(tmp.file("fresh.json")) & 07777, 0644u);
  EXPECT_EQ(tmp.entries(), 3u);
}

TEST(AtomicWrite, FollowsSymbolicLinksAndKeepsThem) {
  TempDir tmp;
  fs::create_directories(tmp.file("real"));
  const std::string target = tmp.write("real/result.json", "old\n");
  ASSERT_EQ(::chmod(target.c_str(), 0640), 0);
  // A relative link to a relative link: each resolved against its own directory.
  fs::create_directories(tmp.file("links"));
  fs::create_symlink("../real/result.json", tmp.file("links/one"));
  fs::create_symlink("one", tmp.file("links/two"));
  OutputFile probe(tmp.file("links/two"));
  EXPECT_EQ(fs::path(probe.target()).lexically_normal(), fs::path(target).lexically_normal());
  WriteFileAtomically(tmp.file("links/two"), "new\n");
  EXPECT_TRUE(S_ISLNK(Lmode(tmp.file("links/two"))));
  EXPECT_TRUE(S_ISLNK(Lmode(tmp.file("links/one"))));
  EXPECT_EQ(ReadText(target), "new\n");
  EXPECT_EQ(Lmode(target) & 07777, 0640u);
  // The temporary went next to the target, and is gone.
  EXPECT_EQ(std::distance(fs::directory_iterator(tmp.file("real")), fs::directory_iterator()), 1);
  EXPECT_EQ(std::distance(fs::directory_iterator(tmp.file("links")), fs::directory_iterator()), 2);
  // A dangling link: its target is created, the link stays.
  fs::create_symlink("real/later.json", tmp.file("dangling"));
  WriteFileAtomically(tmp.file("dangling"), "later\n");
  EXPECT_TRUE(S_ISLNK(Lmode(tmp.file("dangling"))));
  EXPECT_EQ(ReadText(tmp.file("real/later.json")), "later\n");
  // A loop is an error, not a hang.
  fs::create_symlink("loop_b", tmp.file("loop_a"));
  fs::create_symlink("loop_a", tmp.file("loop_b"));
  EXPECT_TRUE(
      Has(MessageOf<imuconv::Error>([&] { OutputFile o(tmp.file("loop_a")); }), "symbolic links"));
}

TEST(AtomicWrite, RefusesAFileWithSeveralHardLinks) {
  TempDir tmp;
  const std::string a = tmp.write("a.json", "shared\n");
  ASSERT_EQ(::link(a.c_str(), tmp.file("b.json").c_str()), 0);
  const std::string msg = MessageOf<imuconv::Error>([&] { WriteFileAtomically(a, "new\n"); });
  EXPECT_TRUE(Has(msg, a + ": has 2 hard links; replacing it would split them")) << msg;
  EXPECT_EQ(ReadText(a), "shared\n");
  EXPECT_EQ(ReadText(tmp.file("b.json")), "shared\n");
  EXPECT_EQ(tmp.entries(), 2u);
}

TEST(AtomicWrite, WritesThroughCharacterDevices) {
  // /dev/null must stay a character device (as root, a rename over it would succeed).
  WriteFileAtomically("/dev/null", "discarded\n");
  EXPECT_TRUE(S_ISCHR(Lmode("/dev/null")));
  OutputFile out("/dev/null");
  EXPECT_EQ(out.mode(), OutputFile::Mode::WriteThrough);
  EXPECT_FALSE(out.is_stdout());
  // A full device: the error names it.
  if (::access("/dev/full", W_OK) == 0) {
    const std::string msg =
        MessageOf<imuconv::Error>([&] { WriteFileAtomically("/dev/full", "x"); });
    EXPECT_TRUE(Has(msg, "/dev/full: cannot write to it: No space left on device")) << msg;
    EXPECT_TRUE(S_ISCHR(Lmode("/dev/full")));
  }
}

TEST(AtomicWrite, WritesThroughAFifoOnlyOnceComplete) {
  TempDir tmp;
  const std::string fifo = tmp.file("pipe");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  std::string received;
  std::thread reader([&] { received = ReadText(fifo); });  // blocks until the writer opens it
  try {
    OutputFile out(fifo);
    EXPECT_EQ(out.mode(), OutputFile::Mode::WriteThrough);
    out.write("{\"a\": ");
    out.write("1}\n");
    out.commit();
  } catch (const std::exception& e) {
    ADD_FAILURE() << e.what();
    ::close(::open(fifo.c_str(), O_WRONLY));  // let the reader finish
  }
  reader.join();
  EXPECT_EQ(received, "{\"a\": 1}\n");
  EXPECT_TRUE(S_ISFIFO(Lmode(fifo)));
  EXPECT_EQ(tmp.entries(), 1u);
  // Not committed (a failing run): a reader waiting in open() gets end-of-file and no data,
  // rather than half a document or a wait that never ends.
  std::atomic<pid_t> tid{0};
  std::atomic<bool> done{false};
  received = "not read";
  std::thread waiting([&] {
    tid = ::gettid();
    received = ReadText(fifo);
    done = true;
  });
  // Until the reader sleeps: in open(), the only call of it that blocks.
  for (int i = 0; i < 10000 && !(tid != 0 && ThreadState(tid) == 'S'); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  {
    OutputFile out(fifo);
    out.write("half a document");
  }
  for (int i = 0; i < 10000 && !done; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  if (!done) {
    ADD_FAILURE() << "the reader was left waiting";
    ::close(::open(fifo.c_str(), O_WRONLY | O_NONBLOCK));
  }
  waiting.join();
  EXPECT_EQ(received, "");
  EXPECT_TRUE(S_ISFIFO(Lmode(fifo)));
}

TEST(AtomicWrite, WritesThroughOurOwnDescriptors) {
  TempDir tmp;
  const std::string log = tmp.write("log.txt", "first line\n");
  const int fd = ::open(log.c_str(), O_WRONLY | O_APPEND | O_CLOEXEC);
  ASSERT_GE(fd, 0);
  // The descriptor is used as it is (here in append mode): the file is neither replaced nor
  // reopened at offset 0.
  for (const std::string& path :
       {"/dev/fd/" + std::to_string(fd), "/proc/self/fd/" + std::to_string(fd)}) {
    OutputFile out(path);
    EXPECT_EQ(out.mode(), OutputFile::Mode::WriteThrough) << path;
    out.write(path + "\n");
    out.commit();
  }
  ::close(fd);
  EXPECT_EQ(ReadText(log), "first line\n/dev/fd/" + std::to_string(fd) + "\n/proc/self/fd/" +
                               std::to_string(fd) + "\n");
  EXPECT_EQ(tmp.entries(), 1u);
  EXPECT_TRUE(OutputFile("-").is_stdout());
  EXPECT_TRUE(OutputFile("/dev/stdout").is_stdout());
  // A descriptor open only for reading is refused up front.
  const int ro = ::open(log.c_str(), O_RDONLY | O_CLOEXEC);
  ASSERT_GE(ro, 0);
  const std::string msg =
      MessageOf<imuconv::Error>([&] { OutputFile o("/dev/fd/" + std::to_string(ro)); });
  ::close(ro);
  EXPECT_TRUE(Has(msg, "is not open for writing")) << msg;
}

TEST(AtomicWrite, RefusesDirectoriesSocketsAndBlockDevices) {
  TempDir tmp;
  fs::create_directories(tmp.file("dir"));
  std::string msg = MessageOf<imuconv::Error>([&] { WriteFileAtomically(tmp.file("dir"), "x"); });
  EXPECT_TRUE(Has(msg, tmp.file("dir") + ": is a directory; expected a regular file")) << msg;

  const std::string sock = tmp.file("sock");
  const int s = ::socket(AF_UNIX, SOCK_STREAM, 0);
  ASSERT_GE(s, 0);
  sockaddr_un addr{};
  addr.sun_family = AF_UNIX;
  ASSERT_LT(sock.size(), sizeof addr.sun_path);
  std::strcpy(addr.sun_path, sock.c_str());
  ASSERT_EQ(::bind(s, reinterpret_cast<sockaddr*>(&addr), sizeof addr), 0);
  msg = MessageOf<imuconv::Error>([&] { WriteFileAtomically(sock, "x"); });
  ::close(s);
  EXPECT_TRUE(Has(msg, sock + ": is a socket")) << msg;

  // Through a link the message names both.
  fs::create_symlink("dir", tmp.file("to_dir"));
  msg = MessageOf<imuconv::Error>([&] { WriteFileAtomically(tmp.file("to_dir"), "x"); });
  EXPECT_TRUE(Has(
      msg, tmp.file("to_dir") + " (a symbolic link to " + tmp.file("dir") + "): is a directory"))
      << msg;

  for (const char* dev : {"/dev/loop0", "/dev/sda", "/dev/vda", "/dev/nvme0n1"}) {
    struct stat st {};
    if (::stat(dev, &st) != 0 || !S_ISBLK(st.st_mode)) continue;
    msg = MessageOf<imuconv::Error>([&] { OutputFile o(dev); });
    EXPECT_TRUE(Has(msg, std::string(dev) + ": is a block device")) << msg;
    EXPECT_TRUE(S_ISBLK(Lmode(dev)));
    break;
  }
  EXPECT_TRUE(
      Has(MessageOf<imuconv::Error>([&] { OutputFile o(""); }), "the output path is empty"));
  EXPECT_EQ(tmp.entries(), 3u);  // dir, sock, to_dir: nothing else
}

TEST(AtomicWrite, RefusesAnOutputThatIsAnInput) {
  TempDir tmp;
  const std::string input = tmp.write("input.csv", "1,2,3\n");
  fs::create_symlink("input.csv", tmp.file("alias.json"));
  for (const std::string& out : {input, tmp.file("alias.json")}) {
    OutputFile o(out);
    const std::string msg =
        MessageOf<imuconv::Error>([&] { o.refuse_if_same(input, "the input file"); });
    EXPECT_EQ(msg, out + ": is the same file as the input file " + input +
                       ": refusing to overwrite it; write the output elsewhere");
  }
  // A different file, and a missing one, are no conflict.
  OutputFile o(tmp.file("result.json"));
  o.refuse_if_same(input, "the input file");
  o.refuse_if_same(tmp.file("missing.csv"), "the input file");
  // Another name of the same inode is refused (here already for its two hard links).
  ASSERT_EQ(::link(input.c_str(), tmp.file("other_name.csv").c_str()), 0);
  EXPECT_TRUE(Has(MessageOf<imuconv::Error>([&] { OutputFile x(tmp.file("other_name.csv")); }),
                  "hard links"));
  EXPECT_EQ(ReadText(input), "1,2,3\n");
}

TEST(AtomicWrite, RefusesASharedObjectThisProcessHasLoaded) {
  // What `imuconv run` checks before its first write: the output is no plugin it loaded. A copy
  // of a plugin in the temp dir, loaded as the registry would load it.
  TempDir tmp;
  const std::string plugin = tmp.file("imuconv_plugin_state_left.so");
  fs::copy_file(std::string(IMUCONV_BINARY_DIR) + "/plugins/imuconv_plugin_state_left.so", plugin);
  const std::string before = ReadText(plugin);
  {
    OutputFile out(plugin);
    out.refuse_if_loaded_object();  // not loaded yet: no conflict
  }
  void* handle = ::dlopen(plugin.c_str(), RTLD_NOW | RTLD_LOCAL);
  ASSERT_NE(handle, nullptr) << ::dlerror();
  OutputFile out(plugin);
  const std::string msg = MessageOf<imuconv::Error>([&] { out.refuse_if_loaded_object(); });
  ::dlclose(handle);
  EXPECT_EQ(msg, plugin + ": is the same file as the loaded plugin or library " + plugin +
                     ": refusing to overwrite it; write the output elsewhere");
  EXPECT_EQ(ReadText(plugin), before);
  EXPECT_EQ(tmp.entries(), 1u);
}

TEST(AtomicWrite, DoesNotRenameOverWhatTheOutputBecameMeanwhile) {
  TempDir tmp;
  const std::string f = tmp.file("out.json");
  OutputFile out(f);
  out.write("text");
  fs::create_directories(f);  // while the run goes on, someone puts a directory there
  const std::string msg = MessageOf<imuconv::Error>([&] { out.commit(); });
  EXPECT_TRUE(Has(msg, f + ": became a directory while the output was produced")) << msg;
  EXPECT_TRUE(fs::is_directory(f));
  EXPECT_EQ(tmp.entries(), 1u);
}

TEST(AtomicWrite, FailingRunsLeaveNoOutput) {
  TempDir tmp;
  // A valid pipeline next to a broken one (interval outside the data: found only after the
  // data is read) and one whose IMU file is missing.
  nlohmann::json doc = nlohmann::json::parse(ReadText(SourcePath("examples/inline_basics.json")));
  const std::string ok = tmp.write("ok.json", doc.dump());
  ASSERT_EQ(doc["tasks"][0]["name"], "direct");
  doc["tasks"][0]["interval"]["t_end"] = 9.0;
  const std::string late = tmp.write("late.json", doc.dump());

  // 1. A new output file is not created.
  const std::string out = tmp.file("result.json");
  CommandResult r = RunImuconv("run " + ShellQuote(late) + " -o " + ShellQuote(out), tmp);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find(late + ": /tasks/0/interval/t_end: t = 9 s is after the last IMU sample"),
            std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(out));

  // 2. An existing output file is left as it was.
  std::ofstream(out) << "previous result\n";
  r = RunImuconv("run " + ShellQuote(late) + " -o " + ShellQuote(out), tmp);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(ReadText(out), "previous result\n");

  // 3. A good run replaces it; no temporaries are left behind in either case.
  r = RunImuconv("run " + ShellQuote(ok) + " -o " + ShellQuote(out) + " --quiet", tmp);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(nlohmann::json::parse(ReadText(out))["tasks"].size(), 10u);
  EXPECT_EQ(tmp.entries(), 3u);  // ok.json, late.json, result.json

  // 4. An output directory that does not exist: an error before the run, nothing written.
  const std::string nowhere = tmp.file("missing/result.json");
  r = RunImuconv("run " + ShellQuote(ok) + " -o " + ShellQuote(nowhere) + " --quiet", tmp);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find(nowhere + ": cannot create a temporary file"), std::string::npos) << r.err;
  EXPECT_EQ(tmp.entries(), 3u);

  // 5. A failing run to a FIFO or to stdout writes nothing there either (held until success).
  r = RunImuconv("run " + ShellQuote(late) + " -o -", tmp);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.out, "");
}

}  // namespace
