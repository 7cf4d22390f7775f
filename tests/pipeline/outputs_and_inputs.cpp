// OutputFile against the inputs of the process and the memory of the work asked
// (docs/outputs.md), through the library (the command-line side:
// tests/cli/inputs_never_written.cpp):
//   - a file read through the one input opener (data::InputFile, so ParseJsonFile and every
//     pipeline reader) is never replaced by an output, by any name, also when it is read
//     after the output was opened; the refusal names it and leaves no temporary;
//   - a written-through output (a device, a FIFO, a descriptor) is spooled to an unlinked
//     file, not held in memory: the peak resident size stays flat however large the document,
//     the bytes arrive whole, and an output that is not committed sends nothing;
//   - no file an output opens takes descriptors 0-2.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <string>
#include <thread>

#include "imuconv/pipeline/json_parse.h"
#include "imuconv/pipeline/output_file.h"
#include "imuconv/pipeline/standard_descriptors.h"
#include "pipeline_test_util.h"

namespace {
using namespace imuconv::test;
using imuconv::pipeline::OutputFile;

/// Runs `body` in a forked child and returns its exit status (0: every check in it held).
/// A child, so that its peak resident size and its descriptors are its own.
template <typename F>
int InChild(F body) {
  const pid_t pid = ::fork();
  if (pid == 0) ::_exit(body());
  int status = 0;
  ::waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status)
                           : 100 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
}

long PeakResidentKiB() {
  rusage u{};
  ::getrusage(RUSAGE_SELF, &u);
  return u.ru_maxrss;  // KiB on Linux
}

TEST(OutputsAndInputs, AFileReadIsNeverReplacedByAnyName) {
  TempDir tmp;
  const std::string input = tmp.write("input.json", "{\"a\": 1}\n");
  fs::create_directories(tmp.file("other"));
  fs::create_symlink(input, tmp.file("other/alias.json"));
  // Opened first, read after: the commit sees the input all the same.
  OutputFile early(tmp.file("other/alias.json"));
  early.write("overwritten\n");
  EXPECT_EQ(imuconv::pipeline::ParseJsonFile(input)["a"], 1);
  const std::string late = MessageOf([&] { early.commit(); });
  EXPECT_TRUE(
      Has(late, "is the same file as the input file " + input + ": refusing to overwrite it"))
      << late;
  // Opened after it was read: refused at once, by its own name and through the link.
  for (const std::string& name :
       {input, tmp.file("other/alias.json"), tmp.file("other/../input.json")}) {
    const std::string m = MessageOf([&] { OutputFile f(name); });
    EXPECT_TRUE(Has(m, "is the same file as the input file " + input)) << name << ": " << m;
  }
  EXPECT_EQ(ReadText(input), "{\"a\": 1}\n");
  EXPECT_EQ(tmp.entries(), 2u) << "no temporary left";
  // Another file is written as before.
  imuconv::pipeline::WriteFileAtomically(tmp.file("out.json"), "fresh\n");
  EXPECT_EQ(ReadText(tmp.file("out.json")), "fresh\n");
}

// Inode numbers are reused: once an input is deleted, a new file may get its number. A
// long-lived process (the Python module) then met a refusal of an output that was never read,
// naming a file that no longer existed. The birth time is part of a file's identity where the
// file system records one (this machine's ext4 and tmpfs do); the reuse itself cannot be forced,
// so the new file is stood in for by the input's identity with another birth time.
TEST(OutputsAndInputs, ANewFileWithADeletedInputsInodeNumberIsNotThatInput) {
  using imuconv::pipeline::FileIdentity;
  using imuconv::pipeline::FindRegisteredInput;
  TempDir tmp;
  const std::string input = tmp.write("read.json", "{\"a\": 2}\n");
  EXPECT_EQ(imuconv::pipeline::ParseJsonFile(input)["a"], 2);
  const auto read = imuconv::pipeline::IdentityAt(AT_FDCWD, input, true);
  ASSERT_TRUE(read.has_value());
  ASSERT_TRUE(FindRegisteredInput(*read).has_value());
  if (!read->has_birth) GTEST_SKIP() << "this file system records no birth time";
  FileIdentity reused = *read;
  reused.birth_nsec = (reused.birth_nsec + 1) % 1000000000u;
  if (reused.birth_nsec == 0) ++reused.birth_sec;
  EXPECT_FALSE(FindRegisteredInput(reused).has_value());
  // A file system without birth times keeps the rule by device and inode alone: refused.
  FileIdentity unknown = *read;
  unknown.has_birth = false;
  EXPECT_TRUE(FindRegisteredInput(unknown).has_value());
}

TEST(OutputsAndInputs, WrittenThroughOutputKeepsMemoryFlat) {
  // 128 MiB to /dev/null in 1 MiB pieces. Held in memory (the old OutputFile) the peak grows
  // by at least 128 MiB; spooled, by the 1 MiB piece, the 1 MiB copy buffer and the
  // allocator's slack (measured: a few hundred KiB). The bound, 32 MiB, is 4 times below what
  // holding the document costs and far above what spooling costs, so neither the allocator
  // nor the page cache (not resident memory of the process) can decide it. No time is measured.
  const int status = InChild([] {
    const std::string piece(std::size_t{1} << 20, 'x');
    const long before = PeakResidentKiB();
    try {
      OutputFile f("/dev/null");
      if (f.mode() != OutputFile::Mode::WriteThrough) return 2;
      for (int i = 0; i < 128; ++i) f.write(piece);
      f.commit();
    } catch (const std::exception& e) {
      std::fprintf(stderr, "%s\n", e.what());
      return 3;
    }
    const long grew = PeakResidentKiB() - before;
    std::fprintf(stderr, "  peak resident size grew by %ld KiB for 128 MiB written through\n",
                 grew);
    return grew < 32 * 1024 ? 0 : 1;
  });
  EXPECT_EQ(status, 0) << "1: memory grew with the document; else a failure (see stderr)";
}

TEST(OutputsAndInputs, SpooledBytesArriveWholeAndOnlyOnCommit) {
  int p[2];
  ASSERT_EQ(::pipe(p), 0);
  std::string received;
  std::thread reader([&] {
    char buf[1 << 16];
    ssize_t n;
    while ((n = ::read(p[0], buf, sizeof buf)) > 0)
      received.append(buf, static_cast<std::size_t>(n));
  });
  std::string sent;
  {
    // Not committed: a failed run sends nothing.
    OutputFile failed("/dev/fd/" + std::to_string(p[1]));
    failed.write("half a document");
  }
  {
    OutputFile f("/dev/fd/" + std::to_string(p[1]));
    for (int i = 0; i < 3000; ++i) {
      const std::string line = "line " + std::to_string(i) + " " +
                               std::string(static_cast<std::size_t>(i % 97), 'y') + "\n";
      sent += line;
      f.write(line);
    }
    f.commit();
  }
  ::close(p[1]);
  reader.join();
  ::close(p[0]);
  EXPECT_EQ(received.size(), sent.size());
  EXPECT_TRUE(received == sent);
}

TEST(OutputsAndInputs, SpoolThatCannotBeMadeIsAClearErrorAndNothingIsSent) {
  const int status = InChild([] {
    ::setenv("TMPDIR", "/nonexistent/imuconv-spool-dir", 1);
    try {
      OutputFile f("/dev/null");
      f.write("text");
    } catch (const std::exception& e) {
      const std::string m = e.what();
      std::fprintf(stderr, "  %s\n", e.what());
      return Has(m, "/dev/null: cannot create the spool file") &&
                     Has(m, "/nonexistent/imuconv-spool-dir") && Has(m, "TMPDIR")
                 ? 0
                 : 1;
    }
    return 2;
  });
  EXPECT_EQ(status, 0);
}

TEST(OutputsAndInputs, NoFileOfOursTakesAStandardDescriptor) {
  // Standard output and input closed in a child; what the output opens (its directory, the
  // temporary, the spool) must not become 0 or 1, so text printed to stdout cannot land in it.
  TempDir tmp;
  const std::string out = tmp.file("out.txt");
  const int status = InChild([&] {
    ::close(0);
    ::close(1);
    try {
      OutputFile f(out);
      f.write("document\n");
      // Anything "printed" now goes to descriptor 1, which must be nobody's.
      if (::write(1, "summary\n", 8) >= 0) return 4;
      f.commit();
      OutputFile spooled("/dev/null");
      spooled.write("x");
      if (::fcntl(0, F_GETFD) != -1 || ::fcntl(1, F_GETFD) != -1) return 5;
      spooled.commit();
    } catch (const std::exception& e) {
      std::fprintf(stderr, "%s\n", e.what());
      return 3;
    }
    // At start-up the tool opens /dev/null onto them instead (main, the Python module).
    imuconv::pipeline::OpenClosedStandardDescriptors();
    if (::fcntl(0, F_GETFD) == -1 || ::fcntl(1, F_GETFD) == -1) return 6;
    if (!imuconv::pipeline::StandardDescriptorWasClosed(1) ||
        imuconv::pipeline::StandardDescriptorWasClosed(2))
      return 7;
    return 0;
  });
  EXPECT_EQ(status, 0);
  EXPECT_EQ(ReadText(out), "document\n");
}

}  // namespace
