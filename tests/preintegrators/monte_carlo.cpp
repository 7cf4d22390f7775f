// The 15x15 covariance of both schemes against Monte Carlo: noisy re-integrations of a
// 1 s slice of a reference case (200 steps), each with white gyro/accel noise
// (variance density^2/dt per held sample) and bias random walks (increments of variance
// density^2 dt), integrated with the unchanged bias estimate. The error of each run is
//   e = [chart(nominal, noisy) (9); -beta_a; -beta_g]
// in the scheme's covariance chart (manifold: NavState local, paper eq. residual-error;
// tangent: difference of the 9-vectors), with beta the accumulated random walk, i.e. the
// bias entry delta b = -Delta b of eq. preint-error-db. Step k sees the random walk
// accumulated before it, as GTSAM's F does.
//
// Check: whitened sample covariance W = L^-1 (1/N sum e e^T) L^-T with Sigma = L L^T must
// be I; for N Gaussian runs its diagonal entries have standard deviation sqrt(2/N) and
// its off-diagonal ones 1/sqrt(N); the NEES mean trace(W) has sqrt(30/N).
//
// The random-walk densities are raised to the white-noise densities (numerically) so that
// the bias cross-covariance X = cov(dx9, db) is large enough (correlations ~0.4) to be
// tested: with the cases' own densities it would be below the Monte Carlo resolution. The
// test then also shows that flipping the sign of X is detected.
#include <gtest/gtest.h>

#include <cstdio>

#include "imuconv/kernels/preintegration.h"
#include "imuconv_test.h"
#include "reference_cases.h"
#include "whitened.h"

namespace {

using namespace imuconv;
using namespace imuconv::test;
namespace k = imuconv::kernels;

using Vec9 = imuconv::Vec9;

struct Slice {
  std::vector<ImuSample> samples;
  PreintegrationInput input;  // window over `samples`
};

Slice MakeSlice(const std::string& id) {
  const ReferenceCase rc = LoadReferenceCase(id);
  Slice s;
  s.samples.assign(rc.samples.begin(), rc.samples.begin() + 201);
  s.input.bg = rc.bg;
  s.input.ba = rc.ba;
  s.input.noise = rc.noise;
  s.input.noise.gyro_random_walk = rc.noise.gyro_noise_density;
  s.input.noise.accel_random_walk = rc.noise.accel_noise_density;
  s.input.window = WindowOver(s.samples);
  return s;
}

/// The nominal (noise-free) increment of both schemes, computed once.
struct Nominal {
  k::ManifoldIncrement manifold;
  k::TangentIncrement tangent;
};

/// The 9 increment components of the scheme's covariance chart, nominal -> noisy.
Vec9 ChartError(const std::string& scheme, const Nominal& x0, const PreintegrationInput& noisy) {
  Preintegrated o;
  if (scheme == "manifold") {
    k::ManifoldIncrement x;
    (void)k::IntegrateManifold<false>(noisy, o, &x);
    const Mat3 Rt = x0.manifold.dR.transpose();
    Vec9 e;
    e << so3::Log(Rt * x.dR), Rt * (x.dp - x0.manifold.dp), Rt * (x.dv - x0.manifold.dv);
    return e;
  }
  k::TangentIncrement x;
  (void)k::IntegrateTangent<false>(noisy, o, &x);
  return x.xi - x0.tangent.xi;
}

void CheckMonteCarlo(const std::string& scheme, const std::string& id) {
  SCOPED_TRACE(scheme + " " + id);
  const Slice s = MakeSlice(id);
  const auto pre = Plugins().preintegrator(scheme);
  Preintegrated out;
  ASSERT_TRUE(pre->integrate(s.input, out).ok());
  const Mat15 Sigma = out.cov;
  Nominal x0;
  ASSERT_TRUE(k::IntegrateManifold<false>(s.input, out, &x0.manifold).ok());
  ASSERT_TRUE(k::IntegrateTangent<false>(s.input, out, &x0.tangent).ok());

  std::mt19937 rng(4242);
  std::normal_distribution<double> n01(0.0, 1.0);
  const auto randn3 = [&] { return Vec3(n01(rng), n01(rng), n01(rng)); };
  const ImuNoise& q = s.input.noise;
  std::vector<Vec15> errors;
  errors.reserve(kRuns);
  std::vector<ImuSample> noisy = s.samples;
  for (int run = 0; run < kRuns; ++run) {
    Vec3 beta_g = Vec3::Zero(), beta_a = Vec3::Zero();
    for (std::size_t j = 0; j + 1 < s.samples.size(); ++j) {
      const double dt = s.samples[j + 1].t - s.samples[j].t;
      noisy[j].gyro =
          s.samples[j].gyro - beta_g - (q.gyro_noise_density / std::sqrt(dt)) * randn3();
      noisy[j].accel =
          s.samples[j].accel - beta_a - (q.accel_noise_density / std::sqrt(dt)) * randn3();
      beta_g += (q.gyro_random_walk * std::sqrt(dt)) * randn3();
      beta_a += (q.accel_random_walk * std::sqrt(dt)) * randn3();
    }
    PreintegrationInput in = s.input;
    in.window = WindowOver(noisy);
    Vec15 e;
    e << ChartError(scheme, x0, in), -beta_a, -beta_g;
    errors.push_back(e);
  }

  const Whitened w = WhitenedStats(Sigma, errors);
  std::printf(
      "[ MC      ] %-8s %-12s N=%d: max|W_ii-1| %.3f (tol %.3f), max|W_ij| %.3f (tol %.3f), NEES "
      "%.3f (15 +- %.3f)\n",
      scheme.c_str(), id.c_str(), kRuns, w.diag, kDiagTol, w.off, kOffTol, w.nees, kNeesTol);
  EXPECT_LT(w.diag, kDiagTol);
  EXPECT_LT(w.off, kOffTol);
  EXPECT_LT(std::abs(w.nees - 15.0), kNeesTol);

  // The test has teeth: the same samples reject the covariance with X's sign flipped.
  Mat15 flipped = Sigma;
  flipped.block<9, 6>(0, 9) *= -1.0;
  flipped.block<6, 9>(9, 0) *= -1.0;
  const Whitened wf = WhitenedStats(flipped, errors);
  std::printf("[ MC      ]   with cov(dx9, db) negated: max|W_ij| %.3f\n", wf.off);
  EXPECT_GT(wf.off, kOffTol);
}

TEST(MonteCarlo, ManifoldAggressive) { CheckMonteCarlo("manifold", "aggressive-0"); }
TEST(MonteCarlo, ManifoldJitter) { CheckMonteCarlo("manifold", "jitter-0"); }
TEST(MonteCarlo, TangentAggressive) { CheckMonteCarlo("tangent", "aggressive-0"); }
TEST(MonteCarlo, TangentJitter) { CheckMonteCarlo("tangent", "jitter-0"); }

}  // namespace
