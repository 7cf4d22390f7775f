// imuconv montecarlo's fast path for a plugin no file of the host names (the plugin interface's
// optional increment_mean(), core/include/imuconv/increment_mean.h), and the guard that keeps a
// wrong one from giving a wrong verdict in silence (apps/montecarlo/montecarlo.cpp,
// kMeanOffsetSigmas). The plugins are tests/fixtures/{user_mean.h,user_euler*.cpp}, loaded from
// their own directory as a user's would be: propagators whose full propagation is the Euler
// kernel, with a right, a deliberately wrong (the midpoint's mean) and a failing
// increment_mean().
//
// Bit for bit against the built-in euler, no tolerance: the right fixture's propagate() and
// increment_mean() call the same kernels, compiled once in imuconv_core, that the built-in
// plugin calls (tests/integrators/mean_only.cpp), and every trial draws the same noise (seed,
// trial index), so the two runs' statistics are the same numbers.
#include <gtest/gtest.h>

#include <cstring>
#include <sstream>
#include <string>

#include "case_input.h"
#include "imuconv_test.h"
#include "montecarlo.h"
#include "montecarlo_report.h"

namespace imuconv::montecarlo {
namespace {

const Registry& WithUserPlugins() {
  static Registry* reg = [] {
    auto* r = new Registry();
    for (const std::string& dir : {Registry::default_plugin_dir(),
                                   std::string(IMUCONV_BINARY_DIR) + "/tests/fixtures/mean_only"})
      for (const LoadIssue& i : r->load_directory(dir))
        ADD_FAILURE() << "plugin failed to load: " << i.file << ": " << i.message;
    return r;
  }();
  return *reg;
}

Result RunUserMethod(const std::string& id, const Input& in, bool allow_mean_only = true) {
  const Registry& reg = WithUserPlugins();
  const PreintegrationMethod method = ResolvePreintegrationMethod(reg, PluginKind::Propagator, id);
  Options o;
  o.trials = 40;
  o.seed = 5;
  o.threads = 2;
  o.allow_mean_only = allow_mean_only;
  return RunMonteCarlo(reg, method, DefaultConvention(method), in, o);
}

bool SameBits(const Mat15& a, const Mat15& b) {
  return std::memcmp(a.data(), b.data(), sizeof(double) * 225) == 0;
}

TEST(MontecarloUserPlugin, ARightMeanOnlyIntegrationIsServedByTheFastPath) {
  const Input in = CaseInput("jitter-0", 1.0);
  const Result user = RunUserMethod("user_euler", in), builtin = RunUserMethod("euler", in);
  EXPECT_EQ(user.trial_path, "mean_only");
  EXPECT_EQ(user.mean_only_offset, 0.0);
  EXPECT_TRUE(user.mean_only_refused.empty()) << user.mean_only_refused;
  // The same scheme as the built-in euler, by the same arithmetic: the same numbers.
  EXPECT_TRUE(SameBits(user.predicted, builtin.predicted));
  EXPECT_TRUE(SameBits(user.stats.sample_cov, builtin.stats.sample_cov));
  EXPECT_EQ(user.stats.nees_mean, builtin.stats.nees_mean);
}

TEST(MontecarloUserPlugin, AWrongMeanOnlyIntegrationIsRefusedAndTheRunSaysSo) {
  const Input in = CaseInput("jitter-0", 1.0);
  const Result wrong = RunUserMethod("user_euler_wrong_mean", in);
  const Result full = RunUserMethod("user_euler_wrong_mean", in, /*allow_mean_only=*/false);
  EXPECT_EQ(wrong.trial_path, "full");
  EXPECT_NE(wrong.mean_only_refused.find("standard deviations of the prediction from the full "
                                         "path's nominal increment"),
            std::string::npos)
      << wrong.mean_only_refused;
  // The trials are the full path's: the same statistics as a run that never tried the fast
  // path, and as the built-in euler's full path (the fixture's propagate() is its kernel).
  EXPECT_TRUE(SameBits(wrong.stats.sample_cov, full.stats.sample_cov));
  EXPECT_EQ(wrong.stats.nees_mean, full.stats.nees_mean);
  EXPECT_TRUE(SameBits(wrong.stats.sample_cov, RunUserMethod("euler", in).stats.sample_cov));
  EXPECT_TRUE(full.mean_only_refused.empty());  // not asked for: nothing refused
  // Said in the outputs a user reads, not only in the Result.
  EXPECT_EQ(ReportJson(wrong).at("mean_only_refused"), wrong.mean_only_refused);
  EXPECT_FALSE(ReportJson(full).contains("mean_only_refused"));
  std::ostringstream summary;
  PrintSummary(summary, wrong);
  EXPECT_NE(
      summary.str().find("its mean-only integration was not used: " + wrong.mean_only_refused),
      std::string::npos)
      << summary.str();
}

TEST(MontecarloUserPlugin, AFailingMeanOnlyIntegrationIsRefusedWithItsMessage) {
  const Input in = CaseInput("smooth-0", 0.5);
  const Result r = RunUserMethod("user_euler_mean_fails", in);
  EXPECT_EQ(r.trial_path, "full");
  EXPECT_NE(r.mean_only_refused.find("fixture user_euler_mean_fails: no mean today"),
            std::string::npos)
      << r.mean_only_refused;
}

// A plugin without the capability (the default "not provided") runs the full path without a
// refusal: nothing was offered.
TEST(MontecarloUserPlugin, APluginWithoutItRunsTheFullPathSilently) {
  const Input in = CaseInput("smooth-0", 0.5);
  const Result r = RunUserMethod("openvins_rk4", in);
  EXPECT_EQ(r.trial_path, "full");
  EXPECT_TRUE(r.mean_only_refused.empty()) << r.mean_only_refused;
}

}  // namespace
}  // namespace imuconv::montecarlo
