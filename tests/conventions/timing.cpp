// Cost of the analytic conversion Jacobians. Each plugin's jacobian_to_reference and
// jacobian_from_reference must stay well below one microsecond (they are block-structured
// fills; they run once per filter step or factor linearisation). The registry's composed
// conversion is printed with its parts for comparison; its cost is the registry's, not the
// plugins'.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>

#include "imuconv_test.h"

namespace {

using imuconv::Mat15;
using imuconv::PluginKind;
using imuconv::test::Plugins;
using Clock = std::chrono::steady_clock;

// The brief's budget for a conversion; a plugin's half of it must fit with room to spare.
constexpr double kPluginBudgetNs = 500.0;
constexpr int kCalls = 20000;
constexpr int kBatches = 7;  // best batch: the machine is shared, the minimum is the cost

template <typename F>
double BestNsPerCall(F&& f) {
  double best = 1e300;
  volatile double sink = 0.0;
  for (int b = 0; b < kBatches; ++b) {
    const auto t0 = Clock::now();
    for (int i = 0; i < kCalls; ++i) sink = sink + f();
    const auto t1 = Clock::now();
    best = std::min(best, std::chrono::duration<double, std::nano>(t1 - t0).count() / kCalls);
  }
  return best;
}

bool OptimisedBuild() {
#ifdef NDEBUG
  return true;
#else
  return false;
#endif
}

TEST(ConversionCost, StatePluginJacobians) {
  if (!OptimisedBuild()) GTEST_SKIP() << "timings are meaningful in optimised builds only";
  const imuconv::ImuState x = imuconv::test::TestStates()[2];
  const auto& reg = Plugins();
  for (const auto& id : reg.ids(PluginKind::StateConvention)) {
    const auto c = reg.state_convention(id);
    Mat15 J;
    const double to = BestNsPerCall([&] { c->jacobian_to_reference(x, J); return J(0, 0); });
    const double from = BestNsPerCall([&] { c->jacobian_from_reference(x, J); return J(0, 0); });
    const double conv = BestNsPerCall([&] { return reg.conversion(id, "gtsam_navstate", x)(0, 0); });
    std::printf("[ timing   ] %-24s to_ref %6.1f ns  from_ref %6.1f ns  | registry conversion to gtsam_navstate %7.1f ns\n",
                id.c_str(), to, from, conv);
    EXPECT_LT(to, kPluginBudgetNs) << id;
    EXPECT_LT(from, kPluginBudgetNs) << id;
  }
  Mat15 A = reg.from_reference("gtsam_navstate", x), B = reg.to_reference("right_invariant_se23", x), C;
  const double product = BestNsPerCall([&] { C.noalias() = A * B; A(0, 0) += 1e-300; return C(0, 0); });
  const double lookups = BestNsPerCall([&] { return reg.to_reference("right_invariant_se23", x)(0, 0) +
                                                    reg.from_reference("gtsam_navstate", x)(0, 0); });
  std::printf("[ timing   ] dense 15x15 product %.1f ns; registry to_reference + from_reference %.1f ns\n", product,
              lookups);
}

TEST(ConversionCost, IncrementPluginJacobians) {
  if (!OptimisedBuild()) GTEST_SKIP() << "timings are meaningful in optimised builds only";
  const imuconv::PreintIncrement x = imuconv::test::TestIncrements()[2];
  const auto& reg = Plugins();
  for (const auto& id : reg.ids(PluginKind::PreintConvention)) {
    const auto c = reg.preint_convention(id);
    Mat15 J;
    const double to = BestNsPerCall([&] { c->jacobian_to_reference(x, J); return J(0, 0); });
    const double from = BestNsPerCall([&] { c->jacobian_from_reference(x, J); return J(0, 0); });
    const double conv = BestNsPerCall([&] { return reg.preint_conversion(id, "gtsam_manifold", x)(0, 0); });
    std::printf("[ timing   ] %-24s to_ref %6.1f ns  from_ref %6.1f ns  | registry conversion to gtsam_manifold %7.1f ns\n",
                id.c_str(), to, from, conv);
    EXPECT_LT(to, kPluginBudgetNs) << id;
    EXPECT_LT(from, kPluginBudgetNs) << id;
  }
}

}  // namespace
