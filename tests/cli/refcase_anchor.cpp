// `imuconv refcase CASE.json --anchor NAME -o OUT.json` against the anchor files themselves
// (tests/data/reference/anchors/NAME/, README.md there): on all ten reference cases, every
// computed field of the anchor file (all but `inputs`, `upstream`, `build`) must be in the
// command's output under the same name and layout, and agree.
//
// Tolerances. Every field: 1e-8 by the metric of J. Huai, "IMU Propagation as Preintegration"
// (relative above 1e-4, absolute below; anchors.h explains the bound: round-off of the same
// formulas accumulated over 2000 steps). VINS-Fusion's whitened fields (factor/sqrt_info,
// factor/whitened/*): 1e-5, because sqrt_info is the Cholesky factor of the inverse of a
// covariance of condition number about 1e9, which turns the covariance's round-off into up to
// about 1e-7 (issue 12). Integer fields (nanosecond times) and strings: equal. For `openvins`
// a method is compared when its propagator is registered (`openvins_discrete` always is); the
// output's methods_written must name exactly those (refcase_anchor_openvins.cpp). For `okvis2`
// the fields that depend on an eigen-solver's choices are judged by what does not depend on
// them (refcase_anchor_okvis2.cpp). Such a system's own rule is declared in a file of its own
// (refcase_anchor.h), so that this file has no case per anchor name (the whitened fields'
// tolerance goes by the fields' names). The worst difference of each field over the ten cases
// is printed.
//
// The anchors judged are every writer `imuconv refcase --anchor` has (refcase::AnchorNames(),
// the table CMake generates from apps/refcase/anchors/) and every fixture directory of
// tests/data/reference/anchors/: a writer without its fixture, or a fixture without its
// writer, fails naming which.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "../pipeline/pipeline_test_util.h"
#include "anchor.h"
#include "imuconv_test.h"
#include "refcase_anchor.h"
#include "scale_aware.h"

namespace {
using namespace imuconv::test;
using namespace imuconv::test::refcase_anchor;
using nlohmann::json;

constexpr double kWhitenedTol = 1e-5;

bool Whitened(const std::string& field) {
  return field.rfind("/factor/sqrt_info", 0) == 0 || field.rfind("/factor/whitened", 0) == 0;
}

/// Compares the anchor's value `a` with the output's `o` at JSON pointer `ptr` (`field` the
/// pointer without indices), recording numeric differences and failing on anything else.
void Compare(const json& a, const json& o, const std::string& ptr, const std::string& field,
             const std::string& label, FieldWorst& worst) {
  if (a.is_object()) {
    ASSERT_TRUE(o.is_object()) << label << ": " << ptr << " is not an object";
    for (auto it = a.begin(); it != a.end(); ++it) {
      if (ptr.empty() && (it.key() == "inputs" || it.key() == "upstream" || it.key() == "build"))
        continue;
      ASSERT_TRUE(o.contains(it.key())) << label << ": the output lacks " << ptr << "/" << it.key();
      Compare(it.value(), o.at(it.key()), ptr + "/" + it.key(), field + "/" + it.key(), label,
              worst);
    }
  } else if (a.is_array()) {
    ASSERT_TRUE(o.is_array() && o.size() == a.size())
        << label << ": " << ptr << " has another size";
    for (std::size_t i = 0; i < a.size(); ++i)
      Compare(a[i], o[i], ptr + "/" + std::to_string(i), field, label, worst);
  } else if (a.is_number_integer()) {
    EXPECT_EQ(a, o) << label << ": " << ptr;
  } else if (a.is_number()) {
    ASSERT_TRUE(o.is_number()) << label << ": " << ptr << " is not a number";
    const double d = EntryDiff(a.get<double>(), o.get<double>());
    double& w = worst[field];
    w = std::max(w, d);
    EXPECT_LE(d, Whitened(field) ? kWhitenedTol : kFieldTol) << label << ": " << ptr;
  } else {
    EXPECT_EQ(a, o) << label << ": " << ptr;
  }
}

void RunAnchor(const std::string& name) {
  TempDir tmp;
  FieldWorst worst;
  for (const char* id : kReferenceCaseIds) {
    const std::string case_path = DataPath(std::string("reference/cases/") + id + ".json");
    const std::string out_path = tmp.file(name + "-" + id + ".json");
    const CommandResult r = RunImuconv(
        "refcase " + ShellQuote(case_path) + " --anchor " + name + " -o " + ShellQuote(out_path),
        tmp);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    json anchor = ReadJson(DataPath("reference/anchors/" + name + "/" + id + ".json"));
    json out = ReadJson(out_path);
    EXPECT_EQ(out.at("anchor"), name);
    const auto& rules = DeclaredFacts<AnchorRules>::All();
    if (const auto rule = rules.find(name); rule != rules.end()) {
      SCOPED_TRACE("the rule declared at " + Describe(rule->second.site));
      rule->second.facts(anchor, out, name + " " + id, worst);
      if (::testing::Test::HasFatalFailure()) return;
    }
    Compare(anchor, out, "", "", name + " " + id, worst);
  }
  std::printf("  %s: worst over the ten cases, by the note's metric\n", name.c_str());
  for (const auto& [field, d] : worst) std::printf("    %-58s %.2g\n", field.c_str(), d);
}

/// The anchors to judge: the writers' names and the fixture directories, each once.
std::vector<std::string> WritersAndFixtures() {
  std::set<std::string> names(imuconv::refcase::AnchorNames().begin(),
                              imuconv::refcase::AnchorNames().end());
  for (const auto& entry : std::filesystem::directory_iterator(DataPath("reference/anchors")))
    if (entry.is_directory()) names.insert(entry.path().filename().string());
  return {names.begin(), names.end()};
}

class RefcaseAnchorFiles : public ::testing::TestWithParam<std::string> {};

TEST_P(RefcaseAnchorFiles, FieldsAreTheSystemsOwn) {
  const std::string& name = GetParam();
  const auto& writers = imuconv::refcase::AnchorNames();
  ASSERT_TRUE(std::find(writers.begin(), writers.end(), name) != writers.end())
      << "tests/data/reference/anchors/" << name << "/ has no writer: `imuconv refcase --anchor "
      << name << "` is refused (a writer is a file of apps/refcase/anchors/)";
  ASSERT_TRUE(std::filesystem::is_directory(DataPath("reference/anchors/" + name)))
      << "the writer `imuconv refcase --anchor " << name
      << "` has no fixture: tests/data/reference/anchors/" << name << "/ is missing";
  RunAnchor(name);
}

INSTANTIATE_TEST_SUITE_P(Anchors, RefcaseAnchorFiles, ::testing::ValuesIn(WritersAndFixtures()),
                         [](const ::testing::TestParamInfo<std::string>& info) {
                           std::string n = info.param;  // a test name is [A-Za-z0-9_]
                           for (char& c : n)
                             if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                           return n;
                         });

TEST(RefcaseAnchor, UnknownNameIsRefusedAndNothingWritten) {
  TempDir tmp;
  const CommandResult r =
      RunImuconv("refcase " + ShellQuote(DataPath("reference/cases/smooth-0.json")) +
                     " --anchor orbslam3 -o " + ShellQuote(tmp.file("out.json")),
                 tmp);
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("orbslam3"), std::string::npos) << r.err;
  EXPECT_FALSE(std::ifstream(tmp.file("out.json")).good());
}

}  // namespace
