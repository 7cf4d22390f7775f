// The portable path of the preintegration kernel (core/src/kernels/portable.cpp) against the
// baseline SIMD instance. With GCC or Clang every Isa, kBaseline included, runs a SIMD
// instance, so the portable path (the only one for a compiler without vector extensions) is
// reached from no public entry point: this test compiles it in and compares the two.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <string>

// The library builds this file hidden; compiled into the test, its functions are the test's own.
#include "../../core/src/kernels/portable.cpp"
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
// products against the SIMD blocks' written-out sums), so they agree to accumulated rounding,
// ~1e-13 relative over these 800-2000-step windows; 1e-11 (as the instances' test against the
// dense recursion, kernels.cpp) leaves margin while a wrong or missing term shows at 1e-4 or more.
constexpr double kPathTol = 1e-11;

TEST(PortablePath, MatchesTheBaselineInstance) {
  double worst = 0.0;
  for (const char* id : {"aggressive-0", "white-0", "smooth-0"}) {
    SCOPED_TRACE(id);
    const ReferenceCase rc = LoadReferenceCase(id);
    const PreintegrationInput in = rc.Input();
    const auto check = [&worst](double e, const char* what) {
      EXPECT_LT(e, kPathTol) << what;
      worst = std::max(worst, e);
    };

    // The two schemes' entry points (NavState chart for manifold, xi for tangent).
    Preintegrated mo, to;
    k::ManifoldIncrement mi, mp;
    k::TangentIncrement ti, tp;
    ASSERT_TRUE(k::IntegrateManifold(in, mo, &mi, k::Isa::kBaseline, true).ok());
    ASSERT_TRUE(k::IntegrateTangent(in, to, &ti, k::Isa::kBaseline, true).ok());
    Mat96 m_J, t_J;
    Mat15 m_cov, t_cov;
    k::detail::ManifoldPortable(in, true, mp, m_J, m_cov);
    k::detail::TangentPortable(in, true, tp, t_J, t_cov);
    check(ScaledErr(mo.cov, m_cov), "manifold cov");
    check(RelErr(mo.J_bias, m_J), "manifold J_bias");
    check(RelErr(mi.dR, mp.dR), "manifold dR");
    check(RelErr(mi.dp, mp.dp), "manifold dp");
    check(RelErr(mi.dv, mp.dv), "manifold dv");
    check(ScaledErr(to.cov, t_cov), "tangent cov");
    check(RelErr(to.J_bias, t_J), "tangent J_bias");
    check(RelErr(ti.xi, tp.xi), "tangent xi");

    // The start-frame route (held-input propagation), both holds.
    for (const k::Hold hold : {k::Hold::Euler, k::Hold::Midpoint}) {
      SCOPED_TRACE(hold == k::Hold::Euler ? "euler hold" : "midpoint hold");
      k::StartFrameManifold s, p;
      ASSERT_TRUE(k::IntegrateManifoldStartFrame(in, hold, true, k::Isa::kBaseline, s).ok());
      k::detail::ManifoldStartFramePortable(in, hold, true, p);
      check(ScaledErr(s.cov, p.cov), "start-frame cov");
      check(RelErr(s.J_inc_bias, p.J_inc_bias), "start-frame J_inc_bias");
      check(RelErr(s.increment.dR, p.increment.dR), "start-frame dR");
      check(RelErr(s.increment.dp, p.increment.dp), "start-frame dp");
      check(RelErr(s.increment.dv, p.increment.dv), "start-frame dv");
    }
  }
  std::printf("[ worst   ] portable path vs baseline instance: %.2e\n", worst);
}

}  // namespace
