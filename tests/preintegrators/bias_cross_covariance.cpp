// The motion-bias blocks of a preintegrated covariance, taken into `gtsam_manifold_jacobian`
// through the registry, against a numeric derivative of the integration with a drifting bias.
//
// Why: a chart's bias sign (Delta b = Delta b^ - db for the GTSAM charts) is consistent with
// its own retract, local and Jacobians whichever it is, and the reference bias Jacobians use
// only the nine motion rows, so a flipped sign in `gtsam_manifold_jacobian` passed every
// numeric test (tests/mutations/ keeps that mutation). What does see it is the sign of the
// correlation between the motion error and the bias error that the random walk makes.
//
// The relation, for the increment over [t_0, T] integrated with the bias estimate b^ while the
// true bias is b(t) = b^ + W(t), W a random walk of density sigma (W(t_0) = 0,
// E[W(t) W(s)^T] = sigma^2 min(t - t_0, s - t_0) I): to first order the motion error is
// linear in the path, e_m = sum_k S_k W(t_k), with S_k the scheme's sensitivity to the bias at
// step k. A deterministic drift W(t) = w (t - t_0) gives e_m = K w with K = sum_k S_k (t_k - t_0),
// and the random walk gives E[e_m W(T)^T] = sum_k S_k sigma^2 (t_k - t_0) = sigma^2 K.
// In `gtsam_manifold_jacobian` (the note's j perturbation, eq. subeq:preint-error-dr..db) the
// motion error is e_m = [Log(Delta R^T Delta R), Delta p - Delta p^, Delta v - Delta v^] and
// the bias coordinate is db = -(Delta b - Delta b^) = -W(T), so its motion-bias block is
//   Sigma_{m,b} = E[e_m db^T] = -sigma^2 K,
// per bias (ba with the accelerometer's random walk, bg with the gyro's). The white noise is
// independent of the walk and adds nothing to this block. K is taken here by central
// differences of a re-integration of samples from which the drift w (t_k - t_0) is
// subtracted, through the same preintegrator, so K and the covariance share one
// discretisation and the chart's definition is the only thing that relates them.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include "imuconv_test.h"
#include "reference_cases.h"
#include "scale_aware.h"

namespace {

using namespace imuconv;
using namespace imuconv::test;

constexpr const char* kChart = "gtsam_manifold_jacobian";

/// The j chart's motion coordinates of `y` about `x`, written from the note's definition
/// (not through the plugin's local): right-perturbed rotation, vector differences.
Vec9 MotionError(const PreintIncrement& x, const PreintIncrement& y) {
  Vec9 e;
  e.segment<3>(0) = so3::Log(x.dR.transpose() * y.dR);
  e.segment<3>(3) = y.dp - x.dp;
  e.segment<3>(6) = y.dv - x.dv;
  return e;
}

/// The increment of `pre` over `samples` when the true bias drifts by `drift_g`, `drift_a` per
/// second from t_0 (the samples are corrected by it; the estimate stays that of the case).
PreintIncrement WithDrift(const Preintegrator& pre, const ReferenceCase& rc, const Vec3& drift_g,
                          const Vec3& drift_a) {
  std::vector<ImuSample> corrected = rc.samples;
  const double t0 = corrected.front().t;
  for (ImuSample& s : corrected) {
    s.gyro -= (s.t - t0) * drift_g;
    s.accel -= (s.t - t0) * drift_a;
  }
  PreintegrationInput in = rc.Input();
  in.window = WindowOver(corrected);
  Preintegrated out;
  EXPECT_TRUE(pre.integrate(in, out).ok());
  return out.delta;
}

class BiasCrossCovariance : public ::testing::TestWithParam<const char*> {};

TEST_P(BiasCrossCovariance, MotionBiasBlocksAreMinusSigmaSquaredTimesDriftResponse) {
  const char* case_id = GetParam();
  const ReferenceCase rc = LoadReferenceCase(case_id);
  for (const char* scheme : {"manifold", "tangent"}) {
    SCOPED_TRACE(std::string(scheme) + " on " + case_id);
    const auto pre = Plugins().preintegrator(scheme);
    Preintegrated nominal;
    ASSERT_TRUE(pre->integrate(rc.Input(), nominal).ok());
    const Mat15 J = Plugins().conversion(pre->cov_convention(), kChart, nominal.delta);
    const Mat15 cov = J * nominal.cov * J.transpose();
    const std::vector<std::string>& blocks =
        Plugins().info(PluginKind::IncrementConvention, kChart).blocks;
    auto offset = [&](const char* label) {
      return 3 * static_cast<int>(std::find(blocks.begin(), blocks.end(), label) - blocks.begin());
    };
    const int theta = offset("theta"), p = offset("p"), v = offset("v"), ba = offset("ba"),
              bg = offset("bg");
    ASSERT_TRUE(ba < 15 && bg < 15);
    // The motion rows [theta, p, v] first, as MotionError writes them.
    ASSERT_TRUE(theta == 0 && p == 3 && v == 6);

    // K by central differences, one drift component at a time. A drift of 1e-6 per second
    // moves the bias by 1e-5 over the 10 s: the response is smooth, so the differencing error
    // is O(h^2) relative (~1e-10), and the re-integrations' rounding (~1e-13 of the increment)
    // over the change (~1e-5 of it) is ~1e-8 relative.
    constexpr double h = 1e-6;
    Eigen::Matrix<double, 9, 6> expected;  // columns: ba's three, then bg's three
    for (int c = 0; c < 6; ++c) {
      Vec3 unit = Vec3::Zero();
      unit[c % 3] = h;
      const bool accel = c < 3;
      const Vec3 g_plus = accel ? Vec3::Zero() : unit, a_plus = accel ? unit : Vec3::Zero();
      const Vec9 K_col = (MotionError(nominal.delta, WithDrift(*pre, rc, g_plus, a_plus)) -
                          MotionError(nominal.delta, WithDrift(*pre, rc, -g_plus, -a_plus))) /
                         (2 * h);
      const double sigma = accel ? rc.noise.accel_random_walk : rc.noise.gyro_random_walk;
      expected.col(c) = -sigma * sigma * K_col;
    }
    Eigen::Matrix<double, 9, 6> actual;
    actual.leftCols<3>() = cov.block<9, 3>(0, ba);
    actual.rightCols<3>() = cov.block<9, 3>(0, bg);

    // Per 3x3 block. Both sides see the walk at the same points (the scheme's covariance
    // recursion is the exact derivative of its discrete map, and the drift is evaluated at the
    // knots t_k it holds), so what is left is the differencing's error, ~1e-8 by the estimate
    // above; measured (GCC 12, x86-64) at most 2.8e-9 (p-ba), 1e-11 on the theta rows. Bound
    // 1e-6: ~300x the measurement, for other instruction sets' rounding; a wrong sign is a
    // relative difference of 2. d theta / d ba is structurally zero on both sides (the
    // rotation does not see the accelerometer): BlockRelativeDiff then demands exact zero.
    const char* rows[3] = {"theta", "p", "v"};
    const char* cols[2] = {"ba", "bg"};
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 2; ++j) {
        const double d = BlockRelativeDiff(expected, actual, i, j);
        std::printf("[ measured ] %s on %s: cov(%s, %s) in %s against -sigma^2 K: %.3g\n", scheme,
                    case_id, rows[i], cols[j], kChart, d);
        EXPECT_LE(d, 1e-6) << rows[i] << "-" << cols[j] << " block\nexpected\n"
                           << expected.block<3, 3>(3 * i, 3 * j) << "\nactual\n"
                           << actual.block<3, 3>(3 * i, 3 * j);
      }
  }
}

INSTANTIATE_TEST_SUITE_P(Cases, BiasCrossCovariance, ::testing::Values("smooth-1", "aggressive-1"),
                         [](const ::testing::TestParamInfo<const char*>& info) {
                           std::string name = info.param;
                           for (char& ch : name)
                             if (ch == '-') ch = '_';
                           return name;
                         });

}  // namespace
