// Plugins are code: what the registry contains at the boundary (exceptions through entry
// points, null and malformed strings, files that are not shared objects, unreadable
// directories, duplicate ids) and what only a child process can (crashes, hangs), through
// the Registry API and the imuconv command line.
//
// The fixtures in tests/fixtures/{crash,hang} kill or hang the process that loads them: they
// are only ever loaded here through `imuconv plugins --check`, in its child processes.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "../pipeline/pipeline_test_util.h"
#include "imuconv/registry.h"
#include "imuconv_test.h"
#include "load_error.h"
#include "processes_mentioning.h"

namespace {
namespace fs = std::filesystem;
using imuconv::Error;
using imuconv::LoadIssue;
using imuconv::LoadOptions;
using imuconv::PluginKind;
using imuconv::Registry;
using imuconv::test::CommandResult;
using imuconv::test::Has;
using imuconv::test::ProcessesMentioning;
using imuconv::test::ShellQuote;
using imuconv::test::TempDir;

std::string Fixture(const std::string& rel) { return imuconv::test::FixturePlugin(rel); }
std::string BuiltIn(const std::string& name) { return imuconv::test::BuiltInPlugin(name); }

// A control byte in a message means a name or id was echoed raw.
bool HasControlByte(const std::string& s) {
  for (unsigned char c : s)
    if (c < 0x20 || c == 0x7f) return true;
  return false;
}

void Copy(const std::string& from, const std::string& to) {
  fs::copy_file(from, to, fs::copy_options::overwrite_existing);
}

std::vector<std::string> Lines(const std::string& text) {
  std::vector<std::string> out;
  std::size_t start = 0;
  while (start < text.size()) {
    const std::size_t nl = text.find('\n', start);
    out.push_back(text.substr(start, nl == std::string::npos ? std::string::npos : nl - start));
    if (nl == std::string::npos) break;
    start = nl + 1;
  }
  return out;
}

// The line of `text` that contains `key`, or "" (one per file in the --check report).
std::string LineWith(const std::string& text, const std::string& key) {
  for (const auto& l : Lines(text))
    if (Has(l, key)) return l;
  return "";
}

// Runs imuconv like RunImuconv, with the sanitizers' SIGSEGV handlers off in a sanitized
// build (so a crashing child dies by the signal, as it does in a normal build), and returns
// the wall time taken.
CommandResult RunCli(const std::string& args, const TempDir& tmp, double* seconds = nullptr) {
  auto with = [](const char* var, const char* extra) {
    const char* old = std::getenv(var);
    return std::string(var) + "=" +
           ShellQuote(std::string(old ? old : "") + (old && *old ? ":" : "") + extra);
  };
  const std::string env = with("ASAN_OPTIONS", "handle_segv=0:handle_sigbus=0") + " " +
                          with("UBSAN_OPTIONS", "handle_segv=0:handle_sigbus=0");
  const std::string out = tmp.file(".stdout"), err = tmp.file(".stderr");
  const std::string cmd = "env -u IMUCONV_PLUGIN_PATH " + env + " " +
                          ShellQuote(imuconv::test::Binary()) + " " + args + " > " +
                          ShellQuote(out) + " 2> " + ShellQuote(err);
  const auto t0 = std::chrono::steady_clock::now();
  const int status = std::system(cmd.c_str());
  if (seconds)
    *seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  CommandResult r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = imuconv::test::ReadText(out);
  r.err = imuconv::test::ReadText(err);
  fs::remove(out);
  fs::remove(err);
  return r;
}

// ---- in-process containment --------------------------------------------------------------

TEST(HostilePlugins, CreateThatThrowsIsALoadErrorNamingTheFile) {
  Registry r;
  const std::string f = Fixture("hostile/imuconv_plugin_create_throws.so");
  const std::string msg = imuconv::test::LoadErrorOf(r, f);
  EXPECT_TRUE(Has(msg, "'" + f + "'")) << msg;
  EXPECT_TRUE(Has(msg,
                  "imuconv_plugin_create() threw an exception: 'fixture: create() refuses to build "
                  "its object'"))
      << msg;
  EXPECT_FALSE(r.has(PluginKind::StateConvention, "create_throws"));
  r.load_file(BuiltIn("imuconv_plugin_state_left.so"));  // still usable
  EXPECT_TRUE(r.has(PluginKind::StateConvention, "left"));
}

TEST(HostilePlugins, NullVersionOrSummaryIsRefusedNamingTheFile) {
  Registry r;
  for (const char* what : {"version", "summary"}) {
    const std::string f = Fixture(std::string("hostile/imuconv_plugin_null_") + what + ".so");
    const std::string msg = imuconv::test::LoadErrorOf(r, f);
    EXPECT_TRUE(Has(msg, "'" + f + "'")) << msg;
    EXPECT_TRUE(Has(msg, std::string("its descriptor's ") + what + " is a null pointer")) << msg;
    EXPECT_FALSE(Has(msg, "basic_string")) << msg;
  }
  EXPECT_EQ(r.plugins().size(), 1u);  // only the built-in preint_reference
}

TEST(HostilePlugins, IdsWithControlBytesAreRefusedAndShownEscaped) {
  Registry r;
  const std::string nl =
      imuconv::test::LoadErrorOf(r, Fixture("hostile/imuconv_plugin_id_newline.so"));
  EXPECT_TRUE(Has(nl, "its descriptor's id 'fake\\n  left 1.0.0 ok' has a character other than"))
      << nl;
  const std::string esc =
      imuconv::test::LoadErrorOf(r, Fixture("hostile/imuconv_plugin_id_escape.so"));
  EXPECT_TRUE(Has(esc, "'esc\\x1b[2Jape'")) << esc;
  const std::string nul =
      imuconv::test::LoadErrorOf(r, Fixture("hostile/imuconv_plugin_id_nul.so"));
  EXPECT_TRUE(Has(nul, "its descriptor's id is empty")) << nul;
  for (const auto& m : {nl, esc, nul}) {
    EXPECT_TRUE(Has(m, "imuconv_plugin_id_")) << m;  // names the file
    EXPECT_FALSE(HasControlByte(m)) << m;
  }
  EXPECT_FALSE(r.has(PluginKind::StateConvention, "left"));  // the NUL fixture's object says "left"
}

TEST(HostilePlugins, EveryHostileFileIsAnIssueAndTheRestOfTheSearchPathLoads) {
  Registry r;
  std::vector<LoadIssue> issues;
  ASSERT_NO_THROW(issues = r.load_search_path({Fixture("hostile")}));
  std::size_t hostile_files = 0;
  for (const auto& e : fs::directory_iterator(Fixture("hostile")))
    hostile_files += e.path().extension() == ".so";
  EXPECT_EQ(hostile_files, 6u);
  EXPECT_EQ(issues.size(), hostile_files);
  for (const auto& i : issues) {
    EXPECT_TRUE(Has(i.file, "/hostile/imuconv_plugin_")) << i.file;
    EXPECT_TRUE(Has(i.message, i.file)) << i.message;  // each message names its file
    EXPECT_FALSE(HasControlByte(i.message)) << i.message;
    EXPECT_FALSE(i.overridden);
  }
  EXPECT_TRUE(r.has(PluginKind::Propagator, "rk4"));
  EXPECT_TRUE(r.has(PluginKind::StateConvention, "left"));
  EXPECT_TRUE(r.has(PluginKind::Preintegrator, "tangent"));
}

TEST(HostilePlugins, FilesThatAreNotSharedObjectsAreNamedForWhatTheyAre) {
  TempDir tmp;
  const std::string empty = tmp.write("imuconv_plugin_empty.so", "");
  const std::string text = tmp.write("imuconv_plugin_text.so", "this is text, not ELF\n");
  // A 64-byte ELF header of a relocatable object (e_type 1): ELF, but no shared object.
  std::string rel(64, '\0');
  rel[0] = 0x7f, rel[1] = 'E', rel[2] = 'L', rel[3] = 'F', rel[4] = 2, rel[5] = 1, rel[6] = 1,
  rel[16] = 1;
  const std::string object = tmp.write("imuconv_plugin_object.so", rel);
  fs::create_directory(tmp.file("imuconv_plugin_dir.so"));
  ASSERT_EQ(::mkfifo(tmp.file("imuconv_plugin_fifo.so").c_str(), 0600),
            0);  // opening it would block

  Registry r;
  const auto issues = r.load_directory(tmp.path());
  ASSERT_EQ(issues.size(), 5u);
  auto message = [&](const std::string& name) {
    for (const auto& i : issues)
      if (i.file == tmp.file(name)) return i.message;
    return std::string("(no issue for " + name + ")");
  };
  EXPECT_EQ(message("imuconv_plugin_empty.so"),
            "cannot load '" + empty +
                "': it is empty (expected an ELF shared object built with imuconv_add_plugin)");
  EXPECT_TRUE(Has(message("imuconv_plugin_text.so"),
                  "cannot load '" + text + "': it is not an ELF shared object"))
      << message("imuconv_plugin_text.so");
  EXPECT_TRUE(Has(message("imuconv_plugin_object.so"),
                  "'" + object + "': it is an ELF file but not a shared object (ELF type 1)"))
      << message("imuconv_plugin_object.so");
  EXPECT_TRUE(Has(message("imuconv_plugin_dir.so"), "it is a directory"))
      << message("imuconv_plugin_dir.so");
  EXPECT_TRUE(Has(message("imuconv_plugin_fifo.so"), "it is not a regular file"))
      << message("imuconv_plugin_fifo.so");
  for (const auto& i : issues) EXPECT_FALSE(Has(i.message, "Bad file descriptor")) << i.message;
}

TEST(HostilePlugins, SharedObjectsForAnotherMachineOrClassAreNamedForWhatTheyAre) {
  // ELF headers of shared objects (e_type 3) this program cannot load: one for another machine
  // (a plugin from the aarch64 cross build on x86-64, or the reverse), one of the other class.
  // dlopen would say only "wrong ELF class" or "cannot open shared object file".
#if defined(__x86_64__) || defined(__aarch64__)
  TempDir tmp;
#if defined(__x86_64__)
  const unsigned char foreign_machine = 183;
  const std::string foreign_name = "aarch64", host_name = "x86-64";
#else
  const unsigned char foreign_machine = 62;
  const std::string foreign_name = "x86-64", host_name = "aarch64";
#endif
  std::string header(64, '\0');
  header[0] = 0x7f, header[1] = 'E', header[2] = 'L', header[3] = 'F', header[4] = 2, header[5] = 1,
  header[6] = 1;
  header[16] = 3;
  header[18] = static_cast<char>(foreign_machine);
  const std::string foreign = tmp.write("imuconv_plugin_foreign.so", header);
  std::string narrow = header;
  narrow[4] = 1;  // ELFCLASS32
  const std::string bits32 = tmp.write("imuconv_plugin_bits32.so", narrow);

  Registry r;
  const auto issues = r.load_directory(tmp.path());
  ASSERT_EQ(issues.size(), 2u);
  for (const auto& i : issues) {
    if (i.file == foreign) {
      EXPECT_TRUE(Has(i.message, "'" + foreign + "': it is an ELF shared object for " +
                                     foreign_name + "; this program runs on " + host_name +
                                     " (rebuild the plugin for this machine)"))
          << i.message;
    } else {
      EXPECT_EQ(i.file, bits32);
      EXPECT_TRUE(Has(i.message,
                      "'" + bits32 + "': it is a 32-bit ELF shared object; this program is 64-bit"))
          << i.message;
    }
  }
#else
  GTEST_SKIP() << "the test names x86-64 and aarch64 only";
#endif
}

// A plugin cut short (an interrupted copy): dlopen maps each segment whether or not the file
// holds it, and touching a missing page is a SIGBUS, so before the check this test crashed its
// own process. Cut inside a mapped segment (half the file), after the segments (the section
// headers at the end lost) and after the ELF header alone: each is named, and nothing is loaded.
TEST(HostilePlugins, ATruncatedPluginIsNamedNotMapped) {
  TempDir tmp;
  std::ifstream in(BuiltIn("imuconv_plugin_state_left.so"), std::ios::binary);
  const std::string whole((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_GT(whole.size(), 4096u);
  for (const std::size_t keep : {whole.size() / 2, whole.size() - 1, std::size_t{64}}) {
    SCOPED_TRACE(keep);
    const std::string cut = tmp.write("imuconv_plugin_cut.so", whole.substr(0, keep));
    Registry r;
    try {
      r.load_file(cut);
      ADD_FAILURE() << "a plugin of " << keep << " of its " << whole.size() << " bytes loaded";
    } catch (const Error& e) {
      EXPECT_TRUE(Has(e.what(), "'" + cut + "': it is a truncated ELF shared object (" +
                                    std::to_string(keep) + " bytes"))
          << e.what();
    }
    EXPECT_EQ(r.plugins().size(), Registry().plugins().size());  // the built-in charts only
  }
}

TEST(HostilePlugins, UnreadableOrMissingDirectoryIsAnIssue) {
  TempDir tmp;
  const std::string missing = tmp.file("missing");
  Registry r;
  auto issues = r.load_directory(missing);
  ASSERT_EQ(issues.size(), 1u);
  EXPECT_EQ(issues[0].file, missing);
  EXPECT_EQ(issues[0].message, "plugin directory does not exist");

  const std::string file = tmp.write("plain", "x");
  issues = r.load_directory(file);
  ASSERT_EQ(issues.size(), 1u);
  EXPECT_EQ(issues[0].message, "plugin directory is not a directory");

  // Permission denied. Root reads any directory, so as root the listing runs in a child
  // process that has given up root first (uid/gid 65534, "nobody").
  const std::string locked = tmp.file("locked");
  fs::create_directory(locked);
  fs::permissions(tmp.path(), fs::perms::owner_all | fs::perms::group_exec |
                                  fs::perms::others_exec);  // reachable for nobody
  fs::permissions(locked, fs::perms::none);
  auto check = [&]() -> std::string {
    Registry reg;
    const auto got = reg.load_directory(locked);
    if (got.size() != 1) return "expected one issue, got " + std::to_string(got.size());
    if (got[0].file != locked) return "issue names " + got[0].file;
    if (got[0].message != "cannot list plugin directory: Permission denied")
      return "message: " + got[0].message;
    return "";
  };
  if (::geteuid() != 0) {
    EXPECT_EQ(check(), "");
    return;
  }
  int pipefd[2];
  ASSERT_EQ(::pipe(pipefd), 0);
  const pid_t pid = ::fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    ::close(pipefd[0]);
    std::string result =
        ::setgid(65534) == 0 && ::setuid(65534) == 0 ? check() : "cannot drop root";
    if (::write(pipefd[1], result.data(), result.size()) < 0) ::_exit(3);
    ::_exit(0);
  }
  ::close(pipefd[1]);
  std::string result;
  char buf[512];
  for (ssize_t n; (n = ::read(pipefd[0], buf, sizeof buf)) > 0;)
    result.append(buf, static_cast<std::size_t>(n));
  ::close(pipefd[0]);
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
  EXPECT_EQ(result, "");
  fs::permissions(locked, fs::perms::owner_all);  // so that TempDir can remove it
}

TEST(HostilePlugins, DuplicateIdOnTheSearchPathIsAnErrorNamingBothFiles) {
  Registry r;
  try {
    (void)r.load_search_path({Fixture("override")});  // expected to throw
    FAIL() << "a second rk4 was accepted";
  } catch (const Error& e) {
    const std::string msg = e.what();
    EXPECT_TRUE(Has(msg, "duplicate propagator plugin id 'rk4': '" +
                             Fixture("override/imuconv_plugin_claims_rk4.so") +
                             "' (found first) and '" +
                             BuiltIn("imuconv_plugin_integrators_rk4.so") + "'"))
        << msg;
    EXPECT_TRUE(Has(msg, "--allow-plugin-override")) << msg;
  }
  // The same through load_directory, for two copies in one directory (two files, one id).
  TempDir tmp;
  Copy(Fixture("override/imuconv_plugin_claims_rk4.so"), tmp.file("imuconv_plugin_a.so"));
  Copy(Fixture("override/imuconv_plugin_claims_rk4.so"), tmp.file("imuconv_plugin_b.so"));
  Registry r2;
  try {
    (void)r2.load_directory(tmp.path());  // expected to throw
    FAIL() << "two files with one id were accepted";
  } catch (const Error& e) {
    EXPECT_TRUE(Has(e.what(), "'" + tmp.file("imuconv_plugin_a.so") + "' (found first) and '" +
                                  tmp.file("imuconv_plugin_b.so") + "'"))
        << e.what();
  }
}

TEST(HostilePlugins, OverrideLetsTheEarlierOneWinWithAWarningNamingBoth) {
  Registry r;
  LoadOptions options;
  options.allow_override = true;
  const auto issues = r.load_search_path({Fixture("override")}, options);
  const std::string fixture = Fixture("override/imuconv_plugin_claims_rk4.so");
  const std::string builtin = BuiltIn("imuconv_plugin_integrators_rk4.so");
  EXPECT_EQ(r.info(PluginKind::Propagator, "rk4").file, fixture);
  EXPECT_EQ(r.info(PluginKind::Propagator, "rk4").version, "0.0.1-fixture");
  ASSERT_EQ(issues.size(), 1u);
  EXPECT_TRUE(issues[0].overridden);
  EXPECT_EQ(issues[0].file, builtin);
  EXPECT_TRUE(Has(issues[0].message, "'" + builtin + "' is ignored and '" + fixture +
                                         "', earlier on the search path, is used"))
      << issues[0].message;
  // The winner is the one that runs: the fixture refuses to integrate.
  imuconv::PropagationInput in;
  EXPECT_THROW((void)r.propagate("rk4", "left", in), Error);
}

TEST(HostilePlugins, TheSameFileUnderTwoNamesIsNoDuplicate) {
  TempDir tmp;
  fs::create_symlink(BuiltIn("imuconv_plugin_integrators_rk4.so"),
                     tmp.file("imuconv_plugin_link.so"));
  Registry r;
  std::vector<LoadIssue> issues;
  ASSERT_NO_THROW(issues = r.load_search_path({tmp.path()}));
  ASSERT_EQ(issues.size(), 1u);
  EXPECT_TRUE(
      Has(issues[0].message, "is already loaded (as '" + tmp.file("imuconv_plugin_link.so") + "')"))
      << issues[0].message;
  EXPECT_TRUE(r.has(PluginKind::Propagator, "rk4"));
}

TEST(HostilePlugins, UnknownIdMessagesShowNulAndControlBytes) {
  Registry r;
  r.load_file(BuiltIn("imuconv_plugin_state_left.so"));
  const std::string id("rk4\0tail\n", 9);
  for (auto call : {+[](Registry&reg, const std::string&i) { (void)reg.propagator(i); },
                    +[](Registry&reg, const std::string&i) {
                      (void)reg.info(PluginKind::StateConvention, i);
                    }}) {
    try {
      call(r, id);
      FAIL();
    } catch (const Error& e) {
      EXPECT_TRUE(Has(e.what(), "'rk4\\0tail\\n' is loaded")) << e.what();
    }
  }
}

// ---- the command line --------------------------------------------------------------------

TEST(HostilePluginsCli, ListingSurvivesBadPluginsAndEscapesTheirNames) {
  TempDir tmp;
  const std::string dir = tmp.file("plugins");
  fs::create_directory(dir);
  // A name that, printed raw, would add a line of its own to the table.
  const std::string fake = dir + "/imuconv_plugin_a.so: ok\nimuconv_plugin_b.so";
  Copy(Fixture("hostile/imuconv_plugin_create_throws.so"), fake);
  Copy(Fixture("hostile/imuconv_plugin_id_escape.so"), dir + "/imuconv_plugin_esc.so");
  tmp.write("plugins/imuconv_plugin_empty.so", "");
  const CommandResult r = RunCli("plugins --plugin-dir " + ShellQuote(dir), tmp);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(Has(r.out, "rk4 ")) << r.out;
  EXPECT_TRUE(Has(r.out, "load errors:\n")) << r.out;
  EXPECT_TRUE(Has(r.out, "  " + dir + "/imuconv_plugin_a.so: ok\\nimuconv_plugin_b.so: plugin '"))
      << r.out;
  EXPECT_TRUE(Has(r.out, "imuconv_plugin_create() threw")) << r.out;
  EXPECT_TRUE(Has(r.out, "'esc\\x1b[2Jape'")) << r.out;
  EXPECT_TRUE(Has(r.out, "imuconv_plugin_empty.so': it is empty")) << r.out;
  for (const auto& line : Lines(r.out)) {
    EXPECT_FALSE(HasControlByte(line)) << line;
    EXPECT_NE(line.rfind("imuconv_plugin_b.so", 0), 0u) << "a file name made its own line:\n"
                                                        << r.out;
  }
  const CommandResult j = RunCli("plugins --json --plugin-dir " + ShellQuote(dir), tmp);
  ASSERT_EQ(j.exit_code, 0) << j.err;
  const auto doc = nlohmann::json::parse(j.out);
  EXPECT_EQ(doc["load_errors"].size(), 3u) << j.out;
  EXPECT_GT(doc["plugins"].size(), 10u);
}

TEST(HostilePluginsCli, DuplicateRk4FailsTheCommandUnlessOverridden) {
  TempDir tmp;
  const std::string dir = Fixture("override");
  CommandResult r = RunCli("plugins --plugin-dir " + ShellQuote(dir), tmp);
  EXPECT_EQ(r.exit_code, 2);  // a duplicate id: bad input (docs/exit-codes.md)
  EXPECT_TRUE(Has(r.err, "imuconv: error: duplicate propagator plugin id 'rk4': '" + dir +
                             "/imuconv_plugin_claims_rk4.so' (found first) and '" +
                             BuiltIn("imuconv_plugin_integrators_rk4.so") + "'"))
      << r.err;
  r = RunCli("plugins --allow-plugin-override --plugin-dir " + ShellQuote(dir), tmp);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(Has(r.out, "\noverridden (--allow-plugin-override):\n  " +
                             BuiltIn("imuconv_plugin_integrators_rk4.so")))
      << r.out;
  EXPECT_TRUE(Has(LineWith(r.out, "  rk4 "), dir + "/imuconv_plugin_claims_rk4.so")) << r.out;
}

TEST(HostilePluginsCli, RunFailsOnADuplicateRk4InThePipelinesPluginDirs) {
  TempDir tmp;
  auto pipeline = imuconv::test::ReadJson(imuconv::test::SourcePath("examples/inline_basics.json"));
  pipeline.erase("$schema");
  pipeline.erase("output");
  pipeline["plugin_dirs"] = {Fixture("override")};
  const std::string path = tmp.write("pipeline.json", pipeline.dump(2));
  const CommandResult r =
      RunCli("run " + ShellQuote(path) + " -q -o " + ShellQuote(tmp.file("out.json")), tmp);
  EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
  EXPECT_TRUE(Has(r.err, "duplicate propagator plugin id 'rk4'")) << r.err;
  EXPECT_TRUE(Has(r.err, Fixture("override/imuconv_plugin_claims_rk4.so"))) << r.err;
  EXPECT_TRUE(Has(r.err, BuiltIn("imuconv_plugin_integrators_rk4.so"))) << r.err;
  EXPECT_FALSE(fs::exists(tmp.file("out.json")));
}

TEST(HostilePluginsCli, CheckNamesCrashesHangsAndErrorsInChildProcesses) {
  TempDir tmp;
  const std::string dir = tmp.file("check");
  fs::create_directory(dir);
  for (const char* f :
       {"crash/imuconv_plugin_labels_segv.so", "crash/imuconv_plugin_labels_throws.so",
        "hang/imuconv_plugin_labels_hang.so", "hostile/imuconv_plugin_create_throws.so"})
    Copy(Fixture(f), dir + "/" + fs::path(f).filename().string());
  Copy(BuiltIn("imuconv_plugin_integrators_rk4.so"), dir + "/imuconv_plugin_rk4.so");
  // A crashing plugin whose name tries to print a fake "ok" line of its own.
  const std::string fake = "imuconv_plugin_z.so: ok (propagator 'x' 1)\n  imuconv_plugin_zz.so";
  Copy(Fixture("crash/imuconv_plugin_labels_segv.so"), dir + "/" + fake);

  double seconds = 0.0;
  const CommandResult r =
      RunCli("plugins --check " + ShellQuote(dir) + " --check-timeout 2", tmp, &seconds);
  EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
  EXPECT_TRUE(Has(r.out, "checking 6 plugin file(s) in '" + dir + "'")) << r.out;
  EXPECT_TRUE(
      Has(LineWith(r.out, "imuconv_plugin_labels_segv.so"), ": crashed with signal SIGSEGV"))
      << r.out;
  EXPECT_TRUE(
      Has(LineWith(r.out, "imuconv_plugin_labels_throws.so"), ": crashed with signal SIGABRT"))
      << r.out;
  EXPECT_TRUE(
      Has(LineWith(r.out, "imuconv_plugin_labels_hang.so"), ": did not finish within 2 s (killed)"))
      << r.out;
  EXPECT_TRUE(Has(LineWith(r.out, "imuconv_plugin_create_throws.so"),
                  "imuconv_plugin_create() threw an exception"))
      << r.out;
  EXPECT_TRUE(Has(LineWith(r.out, "/imuconv_plugin_rk4.so"),
                  ": ok (propagator 'rk4' 1.1.0; propagate() ran on a 10 ms test window)"))
      << r.out;
  EXPECT_TRUE(Has(LineWith(r.out, "imuconv_plugin_z.so"),
                  "1)\\n  imuconv_plugin_zz.so: crashed with signal SIGSEGV"))
      << r.out;
  // One report line per file: the name with a newline did not add one.
  std::size_t report_lines = 0;
  for (const auto& line : Lines(r.out)) {
    EXPECT_FALSE(HasControlByte(line)) << line;
    report_lines += line.rfind("  ", 0) == 0;
  }
  EXPECT_EQ(report_lines, 6u) << r.out;
  EXPECT_TRUE(Has(r.out, "5 of 6 plugin file(s) failed the check")) << r.out;
  // 2 s for the hang, well under a second for the rest; 20 s (the default timeout) would mean
  // --check-timeout was ignored. Generous for sanitized builds on a loaded machine.
  EXPECT_LT(seconds, 20.0);
  EXPECT_EQ(ProcessesMentioning(tmp.path()), std::vector<std::string>{})
      << "a checked child outlived the command";
}

TEST(HostilePluginsCli, CheckOfTheBuiltInPluginsPasses) {
  TempDir tmp;
  const CommandResult r =
      RunCli("plugins --json --check " + ShellQuote(Registry::default_plugin_dir()), tmp);
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["ok"], true);
  std::size_t files = 0;
  for (const auto& e : fs::directory_iterator(Registry::default_plugin_dir()))
    files += e.path().extension() == ".so";
  ASSERT_EQ(j["checked"].size(), files);
  std::size_t costs = 0;
  for (const auto& c : j["checked"]) {
    EXPECT_EQ(c["result"], "ok") << c.dump();
    costs += Has(c["message"].get<std::string>(), "matches what evaluate() writes");
  }
  // Every built-in residual plugin declares its Ceres cost, and each declaration was read
  // against what its evaluate() wrote.
  std::size_t residual_files = 0;
  for (const auto& e : fs::directory_iterator(Registry::default_plugin_dir()))
    residual_files += e.path().filename().string().rfind("imuconv_plugin_residual_", 0) == 0;
  EXPECT_GT(residual_files, 0u);
  EXPECT_EQ(costs, residual_files) << r.out;
}

// A residual plugin's cost declaration (residual_cost_spec.h) is what its Ceres factor is built
// from. --check reads it against what evaluate() writes, so that a broken one is found here and
// not in a user's optimization; one in a chart of the user's own is said to be unchecked.
TEST(HostilePluginsCli, CheckReadsAResidualsCostDeclaration) {
  TempDir tmp;
  const CommandResult r = RunCli("plugins --check " + ShellQuote(Fixture("cost")), tmp);
  EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
  const std::string unwritten = LineWith(r.out, "imuconv_plugin_residual_cost_unwritten.so");
  EXPECT_TRUE(Has(unwritten, "does not write what its cost declaration names")) << r.out;
  EXPECT_TRUE(Has(unwritten, "J_never_written")) << r.out;
  const std::string twice = LineWith(r.out, "imuconv_plugin_residual_cost_block_twice.so");
  EXPECT_TRUE(Has(twice, "its cost declaration is broken")) << r.out;
  EXPECT_TRUE(Has(twice, "start state's block 'p' twice")) << r.out;
  const std::string own = LineWith(r.out, "imuconv_plugin_residual_cost_own_chart.so");
  EXPECT_TRUE(Has(own, ": ok (residual 'toy_cost_own_chart'")) << r.out;
  EXPECT_TRUE(Has(own, "state convention 'toy_chart', which is not built in")) << r.out;
  EXPECT_TRUE(Has(r.out, "2 of 3 plugin file(s) failed the check")) << r.out;
}

TEST(HostilePluginsCli, CheckOfAMissingOrEmptyDirectoryFails) {
  TempDir tmp;
  fs::create_directory(tmp.file("empty"));
  CommandResult r = RunCli("plugins --check " + ShellQuote(tmp.file("empty")), tmp);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(Has(r.out, "no imuconv_plugin_*.so file in '" + tmp.file("empty") + "'")) << r.out;
  r = RunCli("plugins --check " + ShellQuote(tmp.file("missing")), tmp);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(Has(r.out, "plugin directory '" + tmp.file("missing") + "' does not exist")) << r.out;
}

}  // namespace
