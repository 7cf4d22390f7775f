// The bias Jacobians of both schemes against Ridders' differences of a full re-integration
// with a perturbed bias estimate, over the whole 10 s (static: 5 s) of every reference case.
// Each scheme is differentiated in its own chart (paper, "GTSAM Peculiarities"):
//   manifold: Log(dR0^T dR(b)), dp(b) - dp0, dv(b) - dv0   (eq. preint-error-dr..dv);
//   tangent:  xi(b) - xi0 on the 9-vector [theta, p, v], read from the kernel's increment
//             (Log(dR) would equal theta only while |theta| < pi; the scheme never wraps).
// Columns [ba, bg]. Both recursions are exact derivatives of the discrete schemes, so the
// only error is the differencing.
#include <gtest/gtest.h>

#include <cstdio>

#include "imuconv/kernels/preintegration.h"
#include "imuconv/numeric.h"
#include "imuconv_test.h"
#include "reference_cases.h"

namespace {

using namespace imuconv;
using namespace imuconv::test;
namespace k = imuconv::kernels;

// Ridders' extrapolation of re-integrations over 1000-2000 steps: rounding in each
// re-integration (~1e-13 relative) divided by the final steps (~1e-3) bounds the
// attainable accuracy near 1e-10 relative to the largest entry; 1e-8 keeps margin while a
// wrong sign, a missing dt^2/2 term or a stale rotation would be O(1e-3) or larger.
constexpr double kTol = 1e-8;
// Bias steps of 0.01 (rad/s, m/s^2) move theta by < 0.1 rad over 10 s: inside the region
// where the extrapolation converges.
constexpr double kH0 = 0.01;

Mat96 ManifoldNumeric(const PreintegrationInput& in0) {
  k::ManifoldIncrement x0;
  Preintegrated out;
  EXPECT_TRUE(k::IntegrateManifold<false>(in0, out, &x0).ok());
  const Mat15 J = RiddersJacobian(
      [&](const Vec15& d, Vec15& y) {
        PreintegrationInput in = in0;
        in.ba += d.segment<3>(0);
        in.bg += d.segment<3>(3);
        k::ManifoldIncrement x;
        Preintegrated o;
        (void)k::IntegrateManifold<false>(in, o, &x);
        y.setZero();
        y.segment<3>(0) = so3::Log(x0.dR.transpose() * x.dR);
        y.segment<3>(3) = x.dp - x0.dp;
        y.segment<3>(6) = x.dv - x0.dv;
      },
      kH0);
  return J.topLeftCorner<9, 6>();
}

Mat96 TangentNumeric(const PreintegrationInput& in0) {
  k::TangentIncrement x0;
  Preintegrated out;
  EXPECT_TRUE(k::IntegrateTangent<false>(in0, out, &x0).ok());
  const Mat15 J = RiddersJacobian(
      [&](const Vec15& d, Vec15& y) {
        PreintegrationInput in = in0;
        in.ba += d.segment<3>(0);
        in.bg += d.segment<3>(3);
        k::TangentIncrement x;
        Preintegrated o;
        (void)k::IntegrateTangent<false>(in, o, &x);
        y.setZero();
        y.head<9>() = x.xi - x0.xi;
      },
      kH0);
  return J.topLeftCorner<9, 6>();
}

void CheckAgainstReintegration(const std::string& scheme) {
  const auto pre = Plugins().preintegrator(scheme);
  double worst = 0.0;
  std::string worst_case;
  for (const std::string& id : ReferenceCaseIds()) {
    SCOPED_TRACE(id);
    const ReferenceCase rc = LoadReferenceCase(id);
    const PreintegrationInput in = rc.Input();
    Preintegrated out;
    ASSERT_TRUE(pre->integrate(in, out).ok());  // the plugin's J_bias is what is checked
    const Mat96 num = scheme == "manifold" ? ManifoldNumeric(in) : TangentNumeric(in);
    // Block by block ([theta, p, v] x [ba, bg]), so the small theta rows are not judged
    // against the large position entries.
    double e = 0.0;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 2; ++c)
        e = std::max(e,
                     RelErr(out.J_bias.block<3, 3>(3 * r, 3 * c), num.block<3, 3>(3 * r, 3 * c)));
    if (e > worst) worst = e, worst_case = id;
    EXPECT_LT(e, kTol) << "analytic\n" << out.J_bias << "\nnumeric\n" << num;
  }
  std::printf(
      "[ worst   ] %s J_bias vs Ridders re-integration: %.2e (per 3x3 block: max|diff| / max(1, "
      "max|block|)) at %s\n",
      scheme.c_str(), worst, worst_case.c_str());
}

TEST(BiasJacobian, ManifoldMatchesReintegration) { CheckAgainstReintegration("manifold"); }
TEST(BiasJacobian, TangentMatchesReintegration) { CheckAgainstReintegration("tangent"); }

}  // namespace
