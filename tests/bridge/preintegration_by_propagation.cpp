// Paper, section 3.1: the bias Jacobian and covariance obtained by wrapping a propagator,
// checked against central differences of full re-integration and against a Monte Carlo.
#include <gtest/gtest.h>

#include "imuconv/bridge.h"
#include "imuconv/reference_charts.h"
#include "imuconv_test.h"
#include "synthetic.h"

namespace {

using namespace imuconv;
using imuconv::test::Plugins;

class ByPropagation : public ::testing::TestWithParam<const char*> {};

TEST_P(ByPropagation, BiasJacobianMatchesReintegration) {
  const auto imu = test::SmoothImu(1.0);
  const SampleWindow w = test::WholeWindow(imu);
  const Vec3 bg(0.01, -0.02, 0.005), ba(0.1, 0.05, -0.2);
  const Preintegrated m =
      PreintegrateByPropagation(Plugins(), GetParam(), w, bg, ba, test::TestNoise());
  // Central differences of the re-integrated increment in preint_reference, h = 1e-6:
  // truncation ~h^2 |f'''| ~ 1e-12, rounding ~1e-16 |f| / h ~ 1e-10 relative to |J| ~ 0.1..1.
  const double h = 1e-6;
  Mat96 num;
  for (int i = 0; i < 6; ++i) {
    Vec3 dbg = Vec3::Zero(), dba = Vec3::Zero();
    (i < 3 ? dbg[i] : dba[i - 3]) = h;
    const Preintegrated mp =
        PreintegrateByPropagation(Plugins(), GetParam(), w, bg + dbg, ba + dba, test::TestNoise());
    const Preintegrated mm =
        PreintegrateByPropagation(Plugins(), GetParam(), w, bg - dbg, ba - dba, test::TestNoise());
    Vec15 dp, dm;
    PreintReferenceLocal(m.delta, mp.delta, dp);
    PreintReferenceLocal(m.delta, mm.delta, dm);
    num.col(i) = (dp - dm).head<9>() / (2 * h);
  }
  EXPECT_LT(test::RelErr(m.J_bias, num), 1e-6) << "analytic\n" << m.J_bias << "\nnumeric\n" << num;
}

TEST_P(ByPropagation, ExpressAndBackIsLossless) {
  const auto imu = test::SmoothImu(1.0);
  const Preintegrated m =
      PreintegrateByPropagation(Plugins(), GetParam(), test::WholeWindow(imu), Vec3(0.01, 0, 0),
                                Vec3(0, 0.1, 0), test::TestNoise());
  for (const auto& id : Plugins().ids(PluginKind::IncrementConvention)) {
    const Preintegrated back = FromConvention(Plugins(), Express(Plugins(), m, id));
    // Two conversions by exactly inverse Jacobians: rounding only.
    EXPECT_LT(test::RelErr(back.cov, m.cov), 1e-12) << id;
    EXPECT_LT(test::RelErr(back.J_bias, m.J_bias), 1e-12) << id;
  }
}

INSTANTIATE_TEST_SUITE_P(Propagators, ByPropagation, ::testing::Values("euler", "midpoint", "rk4"));

// Monte Carlo of the preintegration covariance (euler, whose noise model is discrete:
// n_k ~ N(0, sigma^2/dt_k) on the sample held over step k, bias random walk
// W_{k+1} = W_k + N(0, sigma_w^2 dt_k), W_0 = 0). The true increment integrates
// omega_m - (b^ + W_k) - n_k; its error in preint_reference is
// [Log(dR^T dR_true), dp_true - dp, dv_true - dv, W_g, W_a] at the last knot.
TEST(ByPropagationMonteCarlo, CovarianceMatchesSampleCovariance) {
  const auto imu = test::SmoothImu(1.0);
  const SampleWindow w = test::WholeWindow(imu);
  const ImuNoise q = test::TestNoise();
  const Vec3 bg(0.01, -0.02, 0.005), ba(0.1, 0.05, -0.2);
  const Preintegrated m = PreintegrateByPropagation(Plugins(), "euler", w, bg, ba, q);

  constexpr int N = 4000;
  std::mt19937 rng(99);
  std::normal_distribution<double> n01(0.0, 1.0);
  auto noise3 = [&](double s) { return Vec3(s * n01(rng), s * n01(rng), s * n01(rng)); };
  Eigen::Matrix<double, 15, Eigen::Dynamic> E(15, N);
  std::vector<ImuSample> noisy(imu.size());
  for (int trial = 0; trial < N; ++trial) {
    Vec3 Wg = Vec3::Zero(), Wa = Vec3::Zero();
    for (std::size_t k = 0; k < imu.size(); ++k) {
      noisy[k] = imu[k];
      if (k + 1 == imu.size()) break;  // the last knot only closes the interval
      const double dt = imu[k + 1].t - imu[k].t;
      noisy[k].gyro -= Wg + noise3(q.gyro_noise_density / std::sqrt(dt));
      noisy[k].accel -= Wa + noise3(q.accel_noise_density / std::sqrt(dt));
      Wg += noise3(q.gyro_random_walk * std::sqrt(dt));
      Wa += noise3(q.accel_random_walk * std::sqrt(dt));
    }
    PropagationInput in;
    in.x_s.bg = bg;
    in.x_s.ba = ba;
    in.gravity.setZero();
    in.noise = q;
    in.window = test::WholeWindow(noisy);
    const PropagationResult r = Plugins().propagate("euler", "left", in);
    PreintIncrement truth;
    truth.dR = r.x_e.R;
    truth.dp = r.x_e.p;
    truth.dv = r.x_e.v;
    truth.dbg = Wg;
    truth.dba = Wa;
    Vec15 e;
    PreintReferenceLocal(m.delta, truth, e);
    E.col(trial) = e;
  }
  test::ExpectCovarianceMatchesSamples(m.cov, E);
}

}  // namespace
