// The schema is the grammar's single source; the hand checker must judge the same documents
// the same way. tests/data/pipeline_cases/cases.json lists pipelines in three groups:
//   accept/    both accept;
//   reject/    both reject: the checker with an issue at the listed pointer and message;
//   semantic/  the schema accepts and the checker rejects by design (plugin ids, times
//              against the data, covariances, references between tasks, ...; each case says
//              why a schema cannot know it).
// This test runs the checker (Pipeline::Load, then every check of a run without running a
// task: RunOptions::check_only) on each of them and on every example pipeline; the pipeline
// schema's verdict on the same files is asserted by tests/pipeline/validate_schemas.py.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <string>

#include "imuconv/pipeline/pipeline.h"
#include "imuconv_test.h"

namespace {
using namespace imuconv;
using namespace imuconv::pipeline;
using nlohmann::json;

const std::string kCases = std::string(IMUCONV_TEST_DATA_DIR) + "/pipeline_cases";

// What the checker says about a pipeline file: "" if it accepts it, else the issues, one
// "POINTER: MESSAGE" per line (a ReadError, which names a file rather than a pointer, as
// ": MESSAGE").
std::string Verdict(const std::string& path) {
  try {
    const Pipeline p = Pipeline::Load(path);
    RunOptions options;
    options.check_only = true;
    options.threads = 1;
    RunToText(p, imuconv::test::Plugins(), options, [](std::string_view) {});
  } catch (const ConfigError& e) {
    std::string s;
    for (const auto& i : e.issues()) s += i.pointer + ": " + i.message + "\n";
    return s;
  } catch (const ReadError& e) {
    return std::string(": ") + e.what() + "\n";
  }
  return "";
}

json Manifest() {
  std::ifstream in(kCases + "/cases.json");
  return json::parse(in);
}

TEST(SchemaCases, TheManifestListsEveryCaseFileOnce) {
  const json m = Manifest();
  std::set<std::string> listed;
  for (const auto& c : m.at("cases"))
    EXPECT_TRUE(listed.insert(c.at("file").get<std::string>()).second) << c;
  std::size_t files = 0;
  for (const char* group : {"accept", "reject", "semantic"})
    for (const auto& e : std::filesystem::directory_iterator(kCases + "/" + group)) {
      ++files;
      EXPECT_TRUE(listed.count(std::string(group) + "/" + e.path().filename().string()))
          << e.path() << " is not in cases.json";
    }
  EXPECT_EQ(files, listed.size());
  EXPECT_GE(listed.size(), 50u);
}

TEST(SchemaCases, TheCheckerJudgesEachCaseAsListed) {
  const json m = Manifest();  // (a temporary's member would not outlive the loop's first line)
  std::size_t judged = 0;
  for (const auto& c : m.at("cases")) {
    ++judged;
    const std::string file = c.at("file").get<std::string>();
    const std::string group = file.substr(0, file.find('/'));
    const std::string verdict = Verdict(kCases + "/" + file);
    if (group == "accept") {
      EXPECT_EQ(verdict, "") << file;
      continue;
    }
    ASSERT_TRUE(group == "reject" || group == "semantic") << file;
    EXPECT_NE(verdict, "") << file << ": accepted by the checker";
    if (group == "semantic") {
      EXPECT_FALSE(c.value("why", "").empty()) << file << ": a by-design case says why";
    }
    // The issue the case is about is among those reported, at its pointer.
    const std::string want = c.value("pointer", "") + ": ";
    const std::string message = c.value("message", "");
    bool found = false;
    for (std::size_t at = verdict.find(want); at != std::string::npos && !found;
         at = verdict.find(want, at + 1)) {
      if (at != 0 && verdict[at - 1] != '\n') continue;
      const std::string line = verdict.substr(at, verdict.find('\n', at) - at);
      found = line.find(message) != std::string::npos;
    }
    EXPECT_TRUE(found) << file << ": expected an issue at '" << c.value("pointer", "") << "' with '"
                       << message << "'; the checker said:\n"
                       << verdict;
  }
  EXPECT_GE(judged, 50u);
}

TEST(SchemaCases, TheCheckerAcceptsEveryExample) {
  std::size_t n = 0;
  for (const auto& e :
       std::filesystem::directory_iterator(std::string(IMUCONV_SOURCE_DIR) + "/examples")) {
    const std::string name = e.path().filename().string();
    if (e.path().extension() != ".json" || name.find(".state.") != std::string::npos ||
        name.find(".measurements.") != std::string::npos)
      continue;
    EXPECT_EQ(Verdict(e.path().string()), "") << name;
    ++n;
  }
  EXPECT_GE(n, 5u);
}

}  // namespace
