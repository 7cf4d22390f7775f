// rk4's noise terms, deterministically. The covariance starts at zero, so the result is the
// noise alone, and each of the four densities is switched on by itself (then all together):
// a wrong factor on any one term is then a relative error of O(1) on the entries it reaches,
// which the correlation scale sees however small those entries are (the bias blocks are
// ~1e-10). The reference is a fine-step solution of the same continuous problem: the
// classical RK4 of dP/dt = F P + P F^T + G Qc G^T with linearly interpolated inputs
// (rk4_reference.h, independent of the kernel's variation-of-constants form), with 16 substeps
// per sample interval, so its own error is 16^4 = 65536x below the kernel's.
// Measured (GCC 12, x86-64): the difference equals the Richardson estimate to 1%, at most
// 2.2e-8 (aggressive-0, up to 6 rad/s), 3e-11 on smooth-0; the gyro random-walk variance
// scaled by 1.001 gives 1e-3 and fails, doubled gives 1.
// Before this test a doubled gyro random-walk term passed every deterministic test: the
// cross-check compares covariances relative to their largest entry, where the random walk
// contributes less than its 3e-8 bound. And while the reference took its variances from the
// kernel's own kernels::NoiseVariances, a doubled accelerometer random-walk variance there
// passed both this test and the cross-check; the reference now squares the densities itself
// (rk4_reference.h), and tests/mutations/ keeps both mutations, caught.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "integrator_cases.h"
#include "rk4_reference.h"
#include "scale_aware.h"

namespace {

using namespace imuconv;
using namespace imuconv::test;

constexpr int kReferenceSubsteps = 16;

struct NoiseTerm {
  const char* name;
  double ImuNoise::*density;  // null: all four
};

const NoiseTerm kTerms[] = {{"gyro_noise_density", &ImuNoise::gyro_noise_density},
                            {"accel_noise_density", &ImuNoise::accel_noise_density},
                            {"gyro_random_walk", &ImuNoise::gyro_random_walk},
                            {"accel_random_walk", &ImuNoise::accel_random_walk},
                            {"all four", nullptr}};

ImuNoise Only(const ImuNoise& n, const NoiseTerm& term) {
  if (!term.density) return n;
  ImuNoise one;
  one.gyro_noise_density = one.accel_noise_density = one.gyro_random_walk = one.accel_random_walk =
      0.0;
  one.*term.density = n.*term.density;
  return one;
}

Mat15 KernelCovariance(const PropagationInput& in, int substeps = 1) {
  PropagationResult r;
  kernels::IntegrateRk4<kernels::Outputs::All>(in, r, substeps);
  return r.cov;
}

Mat15 ReferenceCovariance(const PropagationInput& in) {
  PropagationResult r;
  rk4_reference::IntegrateRk4(in, r, kReferenceSubsteps);
  return r.cov;
}

class Rk4Noise : public ::testing::TestWithParam<const char*> {};

// 2 s (400 sample intervals at 200 Hz) of each case, from a zero start covariance.
TEST_P(Rk4Noise, EachTermMatchesAFineStepLyapunovSolution) {
  const ImuCase c = LoadCase(GetParam());
  PropagationInput in = MakeInput(c, c.samples.front().t, c.samples[400].t);
  in.cov_s.setZero();
  for (const NoiseTerm& term : kTerms) {
    in.noise = Only(c.noise, term);
    const Mat15 kernel = KernelCovariance(in), reference = ReferenceCovariance(in);
    // The bound from the step size: the kernel is fourth order, so its error is ~16/15 of the
    // change from 1 to 2 substeps (Richardson); 4x that, plus 1e-12 for the rounding of 400
    // steps (~400 eps on the correlation scale), allows for the estimate's own next term. A
    // wrong noise factor is an O(1) error, far above it.
    const double richardson = CorrelationScaleDiff(KernelCovariance(in, 2), kernel).d * 16.0 / 15.0;
    const double bound = 4.0 * richardson + 1e-12;
    const ScaledDiff d = CorrelationScaleDiff(reference, kernel);
    std::printf(
        "[ measured ] rk4 on %s (2 s), %s only: correlation-scale difference to the fine-step "
        "reference %.3g at (%d,%d); Richardson estimate %.3g; bound %.3g\n",
        GetParam(), term.name, d.d, d.row, d.col, richardson, bound);
    EXPECT_LT(d.d, bound) << term.name << " at (" << d.row << "," << d.col << "): kernel "
                          << kernel(d.row, d.col) << ", reference " << reference(d.row, d.col);
  }
}

INSTANTIATE_TEST_SUITE_P(Cases, Rk4Noise, ::testing::Values("smooth-0", "aggressive-0", "jitter-0"),
                         CaseTestName);

}  // namespace
