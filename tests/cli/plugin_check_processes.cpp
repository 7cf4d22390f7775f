// imuconv plugins --check and the processes a plugin starts (issue 22). A plugin whose static
// initializer forks a process that leaves the check's process group (setsid()) was reported as
// timing out (that process held the report pipe open) and outlived the command. The checking
// process is now a child subreaper: whatever the plugin started is found once the child has
// exited, killed, and reported as "started a process that outlived it". The second fixture, a
// daemon's double fork that closes every descriptor, is this test's own hostile case: the check
// ended in time before, but the daemon lived on.
//
// Also: a plugin whose descriptor's version is not UTF-8 is flagged by --check and refused by
// every load (the listing's JSON stays JSON).
#include <gtest/gtest.h>

#include <signal.h>

#include <chrono>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "../pipeline/pipeline_test_util.h"
#include "processes_mentioning.h"

namespace {
using namespace imuconv::test;

std::string Fixture(const std::string& rel) {
  return std::string(IMUCONV_BINARY_DIR) + "/tests/fixtures/" + rel;
}

/// The line of `text` that holds `key`.
std::string LineWith(const std::string& text, const std::string& key) {
  const std::size_t at = text.find(key);
  if (at == std::string::npos) return "";
  const std::size_t begin = text.rfind('\n', at), end = text.find('\n', at);
  return text.substr(begin == std::string::npos ? 0 : begin + 1,
                     end == std::string::npos ? end : end - begin - 1);
}

TEST(PluginCheckProcesses, WhatAPluginStartedIsKilledAndNamed) {
  TempDir tmp;
  const std::string dir = tmp.file("check");
  fs::create_directory(dir);
  for (const char* f : {"outlive/imuconv_plugin_setsid_grandchild.so",
                        "outlive/imuconv_plugin_daemon_grandchild.so"})
    fs::copy_file(Fixture(f), dir + "/" + fs::path(f).filename().string());
  const auto start = std::chrono::steady_clock::now();
  const CommandResult r =
      RunImuconv("plugins --check " + ShellQuote(dir) + " --check-timeout 20", tmp);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
  for (const char* name :
       {"imuconv_plugin_setsid_grandchild.so", "imuconv_plugin_daemon_grandchild.so"}) {
    const std::string line = LineWith(r.out, name);
    EXPECT_TRUE(Has(line, "process(es) that outlived it (killed)")) << r.out;
    EXPECT_TRUE(Has(line, "the load itself: ok (state_convention")) << r.out;
    EXPECT_FALSE(Has(line, "did not finish")) << r.out;
  }
  EXPECT_TRUE(Has(r.out, "2 of 2 plugin file(s) failed the check")) << r.out;
  // Not the 20 s timeout: the check ends when the child does (bound generous for a loaded
  // machine or a sanitized build; the two loads take well under a second).
  EXPECT_LT(seconds, 15.0);
  // Nothing outlives the command: a process SIGKILLed and reaped is gone from /proc at once.
  EXPECT_EQ(ProcessesMentioning(dir), std::vector<std::string>{})
      << "a process the plugin started outlived the check";
  // Whatever the result, leave none behind for the next test.
  for (const auto& pid : ProcessesMentioning(dir)) ::kill(std::stoi(pid), SIGKILL);
}

TEST(PluginCheckProcesses, AVersionThatIsNotUtf8IsFlaggedAndRefused) {
  TempDir tmp;
  const std::string dir = Fixture("encoding");
  const CommandResult check = RunImuconv("plugins --check " + ShellQuote(dir), tmp);
  EXPECT_EQ(check.exit_code, 1) << check.out << check.err;
  const std::string line = LineWith(check.out, "imuconv_plugin_version_not_utf8.so");
  EXPECT_TRUE(Has(line, "its descriptor's version '1.0-caf\\xe9-\\xc0\\xaf' is not UTF-8 (byte 7)"))
      << check.out;
  // Listing with it on the search path: a load error, and the JSON listing is JSON.
  const CommandResult j = RunImuconv("plugins --json --plugin-dir " + ShellQuote(dir), tmp);
  EXPECT_EQ(j.exit_code, 0) << j.err;
  const nlohmann::json doc =
      nlohmann::json::parse(j.out);  // throws (a test failure) if it is not JSON
  ASSERT_EQ(doc["load_errors"].size(), 1u) << j.out;
  EXPECT_TRUE(Has(doc["load_errors"][0].dump(), "is not UTF-8")) << j.out;
}

}  // namespace
