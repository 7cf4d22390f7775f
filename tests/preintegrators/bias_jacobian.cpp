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

/// Ridders' differences, in the bias estimate (columns [ba, bg]), of the increment that
/// `integrate(in, out, &increment)` re-integrates, each read in its scheme's own chart by
/// `chart_error(x0, x)` (the 9-vector [theta, p, v] of x against the unperturbed x0).
template <class Increment, class Integrate, class ChartError>
Mat96 NumericBiasJacobian(const PreintegrationInput& in0, Integrate integrate,
                          ChartError chart_error) {
  Increment x0;
  Preintegrated out;
  EXPECT_TRUE(integrate(in0, out, &x0).ok());
  const Mat15 J = RiddersJacobian(
      [&](const Vec15& d, Vec15& y) {
        PreintegrationInput in = in0;
        in.ba += d.segment<3>(0);
        in.bg += d.segment<3>(3);
        Increment x;
        Preintegrated o;
        (void)integrate(in, o, &x);
        y.setZero();
        y.head<9>() = chart_error(x0, x);
      },
      kH0);
  return J.topLeftCorner<9, 6>();
}

Mat96 ManifoldNumeric(const PreintegrationInput& in0) {
  return NumericBiasJacobian<k::ManifoldIncrement>(
      in0,
      [](const PreintegrationInput& in, Preintegrated& out, k::ManifoldIncrement* x) {
        return k::IntegrateManifold<false>(in, out, x);
      },
      [](const k::ManifoldIncrement& x0, const k::ManifoldIncrement& x) {
        Vec9 e;
        e << so3::Log(x0.dR.transpose() * x.dR), x.dp - x0.dp, x.dv - x0.dv;
        return e;
      });
}

Mat96 TangentNumeric(const PreintegrationInput& in0) {
  return NumericBiasJacobian<k::TangentIncrement>(
      in0,
      [](const PreintegrationInput& in, Preintegrated& out, k::TangentIncrement* x) {
        return k::IntegrateTangent<false>(in, out, x);
      },
      [](const k::TangentIncrement& x0, const k::TangentIncrement& x) -> Vec9 {
        return x.xi - x0.xi;
      });
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
