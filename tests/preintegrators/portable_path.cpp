// The portable path of the preintegration kernel (core/src/kernels/portable.cpp, Eigen 3x3
// blocks: what a compiler without vector extensions runs) as the oracle of the SIMD instances.
// Every build has it as Isa::kPortable, so it is reached through the public entry points, and
// every instance this CPU runs (kBaseline, kAvx2, kAvx512) is compared with it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <string>

#include "imuconv/kernels/preintegration.h"
#include "imuconv_test.h"
#include "reference_cases.h"

namespace {

using namespace imuconv;
using namespace imuconv::test;
namespace k = imuconv::kernels;

/// max |a - b| / max|b|: relative to the matrix's own scale (covariances are ~1e-8..1e-1).
template <typename A, typename B>
double ScaledErr(const Eigen::MatrixBase<A>& a, const Eigen::MatrixBase<B>& b) {
  return (a - b).cwiseAbs().maxCoeff() / b.cwiseAbs().maxCoeff();
}

// The two paths run the same first-order recursion in different operation orders (Eigen 3x3
// products against the SIMD blocks' written-out sums; the AVX2 and AVX-512 instances also fuse
// multiply-adds), so they agree to accumulated rounding, ~1e-13 relative over these
// 800-2000-step windows; 1e-11 (as the instances' test against the dense recursion,
// kernels.cpp) leaves margin while a wrong or missing term shows at 1e-4 or more.
constexpr double kPathTol = 1e-11;

TEST(PortablePath, MatchesEveryInstance) {
  double worst = 0.0;
  int instances = 0;
  for (const k::Isa isa : {k::Isa::kBaseline, k::Isa::kAvx2, k::Isa::kAvx512}) {
    if (!k::IsaAvailable(isa)) continue;
    ++instances;
    SCOPED_TRACE(k::IsaName(isa));
    for (const char* id : {"aggressive-0", "white-0", "smooth-0"}) {
      SCOPED_TRACE(id);
      const ReferenceCase rc = LoadReferenceCase(id);
      const PreintegrationInput in = rc.Input();
      const auto check = [&worst](double e, const char* what) {
        EXPECT_LT(e, kPathTol) << what;
        worst = std::max(worst, e);
      };

      // The two schemes' entry points (NavState chart for manifold, xi for tangent).
      Preintegrated mo, to, mpo, tpo;
      k::ManifoldIncrement mi, mp;
      k::TangentIncrement ti, tp;
      ASSERT_TRUE(k::IntegrateManifold(in, mo, &mi, isa, true).ok());
      ASSERT_TRUE(k::IntegrateTangent(in, to, &ti, isa, true).ok());
      ASSERT_TRUE(k::IntegrateManifold(in, mpo, &mp, k::Isa::kPortable, true).ok());
      ASSERT_TRUE(k::IntegrateTangent(in, tpo, &tp, k::Isa::kPortable, true).ok());
      check(ScaledErr(mo.cov, mpo.cov), "manifold cov");
      check(RelErr(mo.J_bias, mpo.J_bias), "manifold J_bias");
      check(RelErr(mi.dR, mp.dR), "manifold dR");
      check(RelErr(mi.dp, mp.dp), "manifold dp");
      check(RelErr(mi.dv, mp.dv), "manifold dv");
      check(ScaledErr(to.cov, tpo.cov), "tangent cov");
      check(RelErr(to.J_bias, tpo.J_bias), "tangent J_bias");
      check(RelErr(ti.xi, tp.xi), "tangent xi");

      // The start-frame route (held-input propagation), both holds.
      for (const k::Hold hold : {k::Hold::Euler, k::Hold::Midpoint}) {
        SCOPED_TRACE(hold == k::Hold::Euler ? "euler hold" : "midpoint hold");
        k::StartFrameManifold s, p;
        ASSERT_TRUE(k::IntegrateManifoldStartFrame(in, hold, true, isa, s).ok());
        ASSERT_TRUE(k::IntegrateManifoldStartFrame(in, hold, true, k::Isa::kPortable, p).ok());
        check(ScaledErr(s.cov, p.cov), "start-frame cov");
        check(RelErr(s.J_inc_bias, p.J_inc_bias), "start-frame J_inc_bias");
        check(RelErr(s.increment.dR, p.increment.dR), "start-frame dR");
        check(RelErr(s.increment.dp, p.increment.dp), "start-frame dp");
        check(RelErr(s.increment.dv, p.increment.dv), "start-frame dv");
      }
    }
  }
  EXPECT_GE(instances, 1);  // kBaseline runs everywhere
  std::printf("[ worst   ] portable path vs %d instances: %.2e\n", instances, worst);
}

// The portable path is a distinct computation, not an alias of the baseline instance: on a
// build with SIMD instances the two orders of operations round differently somewhere in a
// long window's covariance (were they the same code, the comparison above would test nothing).
TEST(PortablePath, IsNotTheBaselineInstance) {
  const ReferenceCase rc = LoadReferenceCase("aggressive-0");
  const PreintegrationInput in = rc.Input();
  Preintegrated base, portable;
  ASSERT_TRUE(k::IntegrateManifold(in, base, nullptr, k::Isa::kBaseline, true).ok());
  ASSERT_TRUE(k::IntegrateManifold(in, portable, nullptr, k::Isa::kPortable, true).ok());
#if defined(__GNUC__)
  EXPECT_NE(base.cov, portable.cov);
#else
  EXPECT_EQ(base.cov, portable.cov);  // no vector extensions: kBaseline is the portable path
#endif
}

// Asking for the portable path is never refused, and auto never picks it.
TEST(PortablePath, AlwaysAvailableNeverAutomatic) {
  EXPECT_TRUE(k::IsaAvailable(k::Isa::kPortable));
  EXPECT_NE(k::BestIsa(), k::Isa::kPortable);
  EXPECT_STREQ(k::IsaName(k::Isa::kPortable), "portable");
}

}  // namespace
