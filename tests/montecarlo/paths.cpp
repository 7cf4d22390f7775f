// imuconv montecarlo's two ways of integrating a trial (apps/montecarlo/montecarlo.cpp): the
// mean alone by the plugin's optional increment_mean() (the built-in plugins give it from the
// core's kernels, kernels/mean_only.h), and the method's full preintegration through its
// plugin. For every method the mean-only path serves, a run each way gives the same
// statistics bit for bit (so the same trials' end errors), and the run says which path it took;
// the other methods take the full path.
//
// Bit for bit, no tolerance: each method the mean-only path serves is a kernel compiled once in
// imuconv_core, which its plugin calls too (rk4's state-only mode is the same compiled function
// as the plugin's full run, core/src/kernels/rk4_window.h, "Instances"), so the run reports a
// zero offset. tests/integrators/mean_only.cpp checks the increments.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstring>

#include "case_input.h"
#include "imuconv_test.h"
#include "montecarlo.h"

namespace imuconv::montecarlo {
namespace {

using test::Plugins;

Result RunMethod(const std::string& method_id, PluginKind kind, const Input& in,
                 bool allow_mean_only) {
  const PreintegrationMethod method = ResolvePreintegrationMethod(Plugins(), kind, method_id);
  Options o;
  o.trials = 40;
  o.seed = 11;
  o.threads = 2;
  o.allow_mean_only = allow_mean_only;
  return RunMonteCarlo(Plugins(), method, DefaultConvention(method), in, o);
}

TEST(MontecarloPaths, MeanOnlyGivesTheFullPathsTrialsBitForBit) {
  for (const char* case_id : {"aggressive-0", "jitter-0"}) {
    const Input in = CaseInput(case_id, 2.0);
    for (const auto& [id, kind] :
         {std::pair<const char*, PluginKind>{"euler", PluginKind::Propagator},
          {"midpoint", PluginKind::Propagator},
          {"rk4", PluginKind::Propagator},
          {"manifold", PluginKind::Preintegrator},
          {"tangent", PluginKind::Preintegrator},
          {"vins_fusion", PluginKind::Preintegrator}}) {
      const Result mean = RunMethod(id, kind, in, true), full = RunMethod(id, kind, in, false);
      EXPECT_EQ(mean.trial_path, "mean_only") << id << " on " << case_id;
      EXPECT_EQ(full.trial_path, "full") << id;
      EXPECT_TRUE(SameBits(mean.predicted, full.predicted)) << id;
      EXPECT_EQ(mean.mean_only_offset, 0.0) << id << " on " << case_id;
      EXPECT_TRUE(SameBits(mean.stats.sample_cov, full.stats.sample_cov))
          << id << " on " << case_id;
      EXPECT_EQ(mean.stats.nees_mean, full.stats.nees_mean) << id;
      EXPECT_EQ(mean.stats.kl, full.stats.kl) << id;
    }
  }
}

// Plugins without increment_mean() run their full preintegration per trial.
TEST(MontecarloPaths, OtherMethodsRunTheFullPath) {
  const Input in = CaseInput("smooth-0", 1.0);
  for (const auto& [id, kind] :
       {std::pair<const char*, PluginKind>{"openvins_rk4", PluginKind::Propagator},
        {"okvis2", PluginKind::Preintegrator},
        {"basalt", PluginKind::Preintegrator}})
    EXPECT_EQ(RunMethod(id, kind, in, true).trial_path, "full") << id;
}

}  // namespace
}  // namespace imuconv::montecarlo
