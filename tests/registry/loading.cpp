// Plugin loading: the built plugins load, and each kind of bad file gives its own error
// while the registry stays usable.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "../pipeline/pipeline_test_util.h"
#include "imuconv_test.h"
#include "load_error.h"

namespace {
namespace fs = std::filesystem;
using imuconv::Error;
using imuconv::PluginKind;
using imuconv::Registry;

std::string PluginFile(const std::string& name) { return imuconv::test::BuiltInPlugin(name); }

/// The error of loading the test fixture plugin `fixture` into a registry of its own.
std::string FixtureLoadError(const std::string& fixture) {
  Registry r;
  return imuconv::test::LoadErrorOf(r, imuconv::test::FixturePlugin(fixture));
}

TEST(Loading, BuiltPluginsLoad) {
  Registry r;
  const auto issues = r.load_directory(Registry::default_plugin_dir());
  EXPECT_TRUE(issues.empty());
  EXPECT_TRUE(r.has(PluginKind::StateConvention, "left"));
  EXPECT_TRUE(r.has(PluginKind::IncrementConvention, "preint_reference"));
  EXPECT_EQ(r.info(PluginKind::StateConvention, "left").blocks,
            (std::vector<std::string>{"p", "theta", "v", "bg", "ba"}));
}

TEST(Loading, MissingFile) {
  Registry r;
  const std::string msg = imuconv::test::LoadErrorOf(r, "/nonexistent/imuconv_plugin_x.so");
  EXPECT_NE(msg.find("does not exist"), std::string::npos) << msg;
  EXPECT_NE(msg.find("/nonexistent/imuconv_plugin_x.so"), std::string::npos) << msg;
}

TEST(Loading, FileThatIsNotASharedLibrary) {
  imuconv::test::TempDir tmp;  // unique: tests run in parallel
  const std::string p = tmp.write("imuconv_plugin_not_a_library.so", "this is text, not ELF\n");
  Registry r;
  const std::string msg = imuconv::test::LoadErrorOf(r, p);
  EXPECT_NE(msg.find("cannot load '" + p + "': it is not an ELF shared object"), std::string::npos)
      << msg;
}

TEST(Loading, SharedLibraryThatIsNotAPlugin) {
  // The registry library itself is a shared object without the plugin aliases.
  Registry r;
  const std::string lib = std::string(IMUCONV_BINARY_DIR) + "/lib/libimuconv_core.so";
  const std::string msg = imuconv::test::LoadErrorOf(r, lib);
  EXPECT_NE(msg.find("is not an imuconv plugin"), std::string::npos) << msg;
}

TEST(Loading, WrongAbiVersion) {
  const std::string msg = FixtureLoadError("imuconv_plugin_wrong_abi.so");
  EXPECT_NE(msg.find("ABI version 999"), std::string::npos) << msg;
}

TEST(Loading, DuplicateIdNamesBothFiles) {
  Registry r;
  r.load_file(PluginFile("imuconv_plugin_state_left.so"));
  const std::string dup = imuconv::test::FixturePlugin("imuconv_plugin_duplicate_left.so");
  const std::string msg = imuconv::test::LoadErrorOf(r, dup);
  EXPECT_NE(msg.find("duplicate"), std::string::npos) << msg;
  EXPECT_NE(msg.find("imuconv_plugin_state_left.so"), std::string::npos) << msg;
  EXPECT_NE(msg.find("imuconv_plugin_duplicate_left.so"), std::string::npos) << msg;
}

TEST(Loading, WrongAnalyticJacobianIsRefused) {
  const std::string msg = FixtureLoadError("imuconv_plugin_bad_jacobian.so");
  EXPECT_NE(msg.find("analytic J_ref_this differs"), std::string::npos) << msg;
}

TEST(Loading, BlockOrderThatIsNoPermutationIsRefused) {
  const std::string msg = FixtureLoadError("imuconv_plugin_bad_order.so");
  EXPECT_NE(msg.find("state convention 'bad_order'"), std::string::npos) << msg;
  EXPECT_NE(
      msg.find(
          "block order must be a permutation of p, theta, v, bg, ba (got theta, theta, v, bg, ba)"),
      std::string::npos)
      << msg;
}

TEST(Loading, RegistryStaysUsableAfterFailures) {
  Registry r;
  imuconv::test::LoadErrorOf(r, "/nonexistent.so");
  imuconv::test::LoadErrorOf(r, imuconv::test::FixturePlugin("imuconv_plugin_wrong_abi.so"));
  imuconv::test::LoadErrorOf(r, imuconv::test::FixturePlugin("imuconv_plugin_bad_jacobian.so"));
  r.load_file(PluginFile("imuconv_plugin_state_left.so"));
  imuconv::ImuState x;
  EXPECT_TRUE(r.conversion("left", "left", x).isIdentity());
  EXPECT_FALSE(r.has(PluginKind::StateConvention, "bad_jacobian"));
}

TEST(Loading, UnknownIdListsKnownOnes) {
  Registry r;
  r.load_file(PluginFile("imuconv_plugin_state_left.so"));
  try {
    (void)r.state_convention("nope");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("known: left"), std::string::npos) << e.what();
  }
}

}  // namespace
