// Transition matrices of the three integrators against central differences of the whole
// nonlinear propagation, the exactness of the Euler step Jacobian, and the kernels' block-
// sparse algebra against the dense 15x15 formulas it replaces.
#include <gtest/gtest.h>

#include <iostream>
#include <string>

#include "imuconv/numeric.h"
#include "integrator_cases.h"
#include "rk4_reference.h"

namespace {

using namespace imuconv;
using namespace imuconv::test;
using kernels::Outputs;
namespace li = imuconv::left_idx;

// Phi = d local(x_e, propagate(retract(x_s, d))) / d d at d = 0, by Ridders' extrapolation of
// the state-only kernel: the same discrete map whose Jacobian Phi claims to be. Not one central
// difference: the per-sample route (IntegrateHeldPerSample, which every CPU without AVX2 runs,
// aarch64 included) rounds the state itself at each of ~200 steps, and that noise over h puts
// a floor under a single step size: 2.4e-10 .. 3.7e-10 at h = 1e-5 (the same digits on x86-64
// forced to that route and on aarch64 under qemu), never below 1.1e-10 for h in 5e-6 .. 8e-5,
// above the exact-Jacobian bound. The preintegration route (AVX2, AVX-512) rounds only small
// increments and reached 2.5e-11 .. 6.4e-11 at h = 1e-5.
Mat15 NumericPhi(Integrator integrator, const PropagationInput& in, const ImuState& x_e) {
  return RiddersJacobian([&](const Vec15& d, Vec15& out) {
    PropagationInput perturbed = in;
    LeftRetract(in.x_s, d, perturbed.x_s);
    PropagationResult r;
    RunKernel<Outputs::State>(integrator, perturbed, r);
    LeftLocal(x_e, r.x_e, out);
  });
}

struct PhiCase {
  Integrator integrator;
  const char* data;
  double bound;  // on max|Phi - Phi_fd| / max|Phi_fd|, see the instantiation below
};

class PhiVsFiniteDifferences : public ::testing::TestWithParam<PhiCase> {};

TEST_P(PhiVsFiniteDifferences, OneSecond) {
  const PhiCase pc = GetParam();
  const ImuCase c = LoadCase(pc.data);
  // 1 s starting and ending between samples, so interpolated first and last knots are included.
  const double t_s = c.samples[100].t + 0.37 * (c.samples[101].t - c.samples[100].t);
  const PropagationInput in = MakeInput(c, t_s, t_s + 1.0);
  PropagationResult r;
  RunKernel(pc.integrator, in, r);
  const Mat15 numeric = NumericPhi(pc.integrator, in, r.x_e);
  const double rel = RelChange(r.Phi, numeric);
  std::cout << "[ measured ] " << Name(pc.integrator) << " on " << pc.data
            << ": max|Phi - Phi_fd| / max|Phi_fd| = " << rel
            << " (max|Phi| = " << numeric.cwiseAbs().maxCoeff() << ")\n";
  RecordProperty("phi_fd_rel_error", std::to_string(rel));
  EXPECT_LT(rel, pc.bound) << "bound stated in the instantiation";
}

// Bounds per integrator and case, just above what each reaches (GCC 12; x86-64 on both routes
// and aarch64 under qemu; the specification's 1e-6 let a wrong RK4 weight through).
//  - euler and midpoint give the exact Jacobian of their discrete map, so only Ridders'
//    extrapolation error remains: measured 5e-14 .. 1.7e-13 on the preintegration route,
//    3.6e-13 .. 1.1e-12 on the per-sample route (x86-64 and aarch64): bound 1e-11. A dropped term
//    of the step Jacobian is ~|w dt|^2 ~ 1e-3 relative.
//  - rk4's Phi solves the variational equation to fourth order, which differs from the
//    derivative of the discrete map by O(dt^4 |w|^4): smooth-0 2.7e-11, jitter-0 1.3e-10
//    (steps up to 1.4x the nominal one), aggressive-0 1.4e-8 (up to 6 rad/s); bounds 2e-10,
//    5e-10 and 3e-8 (set with single central differences, which read 8.0e-11, 1.6e-10 and
//    1.4e-8). One quadrature weight of rk4's Phi off by 2e-7 (2.0000004 for 2) gave 3.6e-8
//    on smooth-0, 4.4e-8 on aggressive-0, 2.9e-8 on jitter-0 with central differences: an
//    error of Phi itself, far above either estimator's floor, so all three fail.
constexpr double kExactFd = 1e-11;

INSTANTIATE_TEST_SUITE_P(Integrators, PhiVsFiniteDifferences,
                         ::testing::Values(PhiCase{Integrator::Euler, "smooth-0", kExactFd},
                                           PhiCase{Integrator::Euler, "aggressive-0", kExactFd},
                                           PhiCase{Integrator::Euler, "jitter-0", kExactFd},
                                           PhiCase{Integrator::Midpoint, "smooth-0", kExactFd},
                                           PhiCase{Integrator::Midpoint, "aggressive-0", kExactFd},
                                           PhiCase{Integrator::Midpoint, "jitter-0", kExactFd},
                                           PhiCase{Integrator::Rk4, "smooth-0", 2e-10},
                                           PhiCase{Integrator::Rk4, "aggressive-0", 3e-8},
                                           PhiCase{Integrator::Rk4, "jitter-0", 5e-10}),
                         [](const ::testing::TestParamInfo<PhiCase>& info) {
                           std::string name =
                               std::string(Name(info.param.integrator)) + "_" + info.param.data;
                           for (char& ch : name)
                             if (ch == '-') ch = '_';
                           return name;
                         });

// Random state with a large rotation rate so that Jr(w dt) is far from I.
ImuState RandomState() {
  ImuState x;
  x.R = so3::Exp(RandVec(1.0));
  x.p = RandVec(10.0);
  x.v = RandVec(3.0);
  x.bg = RandVec(0.05);
  x.ba = RandVec(0.2);
  return x;
}

TEST(EulerStep, JacobianIsExact) {
  for (int trial = 0; trial < 5; ++trial) {
    const ImuState x = RandomState();
    const Vec3 gyro = RandVec(3.0), accel = RandVec(10.0), g(0, 0, -9.81);
    const double dt = 0.02;
    ImuState x1;
    kernels::EulerStepJacobian J;
    kernels::EulerStep<true>(x, gyro, accel, dt, g, x1, &J);
    // Ridders' extrapolation resolves ~1e-12: tight enough to see any dropped term of the
    // exact discrete Jacobian (a first-order approximation would be off by ~|w dt|^2 ~ 4e-3).
    const Mat15 numeric = RiddersJacobian([&](const Vec15& d, Vec15& out) {
      ImuState xp, yp;
      LeftRetract(x, d, xp);
      kernels::EulerStep<false>(xp, gyro, accel, dt, g, yp, nullptr);
      LeftLocal(x1, yp, out);
    });
    EXPECT_LT(RelChange(J.ToTransition().ToMatrix(), numeric), 1e-10) << "trial " << trial;
    // The noise enters as w = w_m - bg - n_g and a = a_m - ba - n_a: same columns as the biases.
    const Mat15 noise_numeric = RiddersJacobian([&](const Vec15& d, Vec15& out) {
      ImuState yp;
      kernels::EulerStep<false>(x, gyro - d.segment<3>(li::bg), accel - d.segment<3>(li::ba), dt, g,
                                yp, nullptr);
      LeftLocal(x1, yp, out);
    });
    // (Rows p, theta, v: the noise does not enter the bias rows, which hold the identity for dbg,
    // dba.)
    EXPECT_LT(RelChange(J.ToTransition().ToMatrix().topRightCorner<9, 6>(),
                        noise_numeric.topRightCorner<9, 6>()),
              1e-10);
  }
}

// Dense reference of one Euler covariance step: A P A^T + B Qd B^T + W.
Mat15 DenseEulerCovariance(const kernels::EulerStepJacobian& J, const ImuNoise& n, const Mat15& P) {
  const Mat15 A = J.ToTransition().ToMatrix();
  Eigen::Matrix<double, 15, 6> B = Eigen::Matrix<double, 15, 6>::Zero();
  B.leftCols<3>() = A.middleCols<3>(li::bg) - Mat15::Identity().middleCols<3>(li::bg);
  B.rightCols<3>() = A.middleCols<3>(li::ba) - Mat15::Identity().middleCols<3>(li::ba);
  Eigen::Matrix<double, 6, 1> qd;
  qd << Vec3::Constant(n.gyro_noise_density * n.gyro_noise_density / J.dt),
      Vec3::Constant(n.accel_noise_density * n.accel_noise_density / J.dt);
  Mat15 W = Mat15::Zero();
  W.block<3, 3>(li::bg, li::bg)
      .diagonal()
      .setConstant(n.gyro_random_walk * n.gyro_random_walk * J.dt);
  W.block<3, 3>(li::ba, li::ba)
      .diagonal()
      .setConstant(n.accel_random_walk * n.accel_random_walk * J.dt);
  return A * P * A.transpose() + B * qd.asDiagonal() * B.transpose() + W;
}

Mat15 RandomCovariance() {
  std::normal_distribution<double> normal(0.0, 1.0);
  Mat15 L = Mat15::Zero();
  for (int i = 0; i < 15; ++i)
    for (int j = 0; j <= i; ++j) L(i, j) = (i == j ? 1.0 : 0.3) * normal(Rng());
  return L * L.transpose();
}

ImuNoise SomeNoise() {
  ImuNoise n;
  n.gyro_noise_density = 0.01;
  n.accel_noise_density = 0.1;
  n.gyro_random_walk = 0.002;
  n.accel_random_walk = 0.02;
  return n;
}

TEST(BlockSparseAlgebra, EulerCovarianceStepMatchesDense) {
  const ImuNoise n = SomeNoise();
  for (int trial = 0; trial < 5; ++trial) {
    const ImuState x = RandomState();
    ImuState x1;
    kernels::EulerStepJacobian J;
    kernels::EulerStep<true>(x, RandVec(3.0), RandVec(10.0), 0.01, Vec3(0, 0, -9.81), x1, &J);
    const Mat15 P0 = RandomCovariance();
    Mat15 P = P0;
    kernels::EulerCovarianceStep(J, kernels::NoiseVariances(n), P);
    // Same sums in another order: rounding only.
    EXPECT_LT(RelChange(P, DenseEulerCovariance(J, n, P0)), 1e-14) << "trial " << trial;
  }
}

TEST(BlockSparseAlgebra, TransitionCompositionMatchesDense) {
  auto random_transition = [] {
    kernels::LeftTransition T;
    for (Mat3* m : {&T.th_bg, &T.v_th, &T.v_bg, &T.v_ba, &T.p_th, &T.p_bg, &T.p_ba})
      *m = Mat3::Random();
    T.p_v = 0.7;
    return T;
  };
  kernels::LeftTransition a = random_transition();
  const kernels::LeftTransition s = random_transition();
  const Mat15 dense = s.ToMatrix() * a.ToMatrix();
  a.PrependStep(s);
  // 15x15 product of O(1) entries: rounding ~1e-15.
  EXPECT_LT(RelChange(a.ToMatrix(), dense), 1e-14);
}

// The rates of the classical RK4 reference (rk4_reference.h), F M and F P + P F^T + D, against
// the dense F; D against the densities squared written out here.
TEST(BlockSparseAlgebra, Rk4ReferenceRatesMatchDense) {
  const ImuNoise n = SomeNoise();
  const Mat3 R = so3::Exp(RandVec(1.0));
  const Vec3 Ra = RandVec(10.0);
  const Mat15 P = RandomCovariance(), M = Mat15::Random();
  Mat15 F = Mat15::Zero();
  F.block<3, 3>(li::p, li::v).setIdentity();
  F.block<3, 3>(li::theta, li::bg) = -R;
  F.block<3, 3>(li::v, li::theta) = -so3::skew(Ra);
  F.block<3, 3>(li::v, li::ba) = -R;
  const Vec15 D = rk4_reference::rk4_detail::ProcessNoiseDiagonal(n);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(D(li::p + i), 0.0);
    EXPECT_EQ(D(li::theta + i), 0.01 * 0.01);
    EXPECT_EQ(D(li::v + i), 0.1 * 0.1);
    EXPECT_EQ(D(li::bg + i), 0.002 * 0.002);
    EXPECT_EQ(D(li::ba + i), 0.02 * 0.02);
  }
  const Mat15 dense = F * P + P * F.transpose() + Mat15(D.asDiagonal());
  EXPECT_LT(RelChange(rk4_reference::rk4_detail::CovarianceRate(R, Ra, P, D), dense),
            1e-14);  // rounding only
  EXPECT_LT(RelChange(rk4_reference::rk4_detail::ErrorRateTimes(R, Ra, M), F * M),
            1e-14);  // rounding only
}

// The theta columns come from the state (ThetaColumnsFromState); accumulating them step by
// step with the generic composition must give the same blocks.
TEST(BlockSparseAlgebra, ThetaColumnsFromStateMatchAccumulation) {
  const ImuCase c = LoadCase("aggressive-0");
  const PropagationInput in = MakeInput(c, c.samples[0].t, c.samples[400].t);
  PropagationResult r;
  RunKernel<Outputs::StateAndTransition>(Integrator::Euler, in, r);
  kernels::LeftTransition accumulated;
  ImuState x = in.x_s;
  for (std::size_t k = 0; k + 1 < in.window.size(); ++k) {
    kernels::EulerStepJacobian J;
    kernels::EulerStep<true>(x, in.window[k].gyro, in.window[k].accel,
                             in.window[k + 1].t - in.window[k].t, in.gravity, x, &J);
    accumulated.PrependStep(J.ToTransition());
  }
  // 400 steps of O(1)..O(10) sums: rounding ~1e-13 relative.
  EXPECT_LT(RelChange(r.Phi, accumulated.ToMatrix()), 1e-12);
}

TEST(KernelOutputs, ModesAgree) {
  const ImuCase c = LoadCase("smooth-0");
  const PropagationInput in = MakeInput(c, c.samples[10].t, c.samples[300].t);
  for (Integrator i : kIntegrators) {
    PropagationResult state, phi, all;
    RunKernel<Outputs::State>(i, in, state);
    RunKernel<Outputs::StateAndTransition>(i, in, phi);
    RunKernel<Outputs::All>(i, in, all);
    // The state never depends on what else is computed: bitwise equal.
    EXPECT_EQ(state.x_e.R, all.x_e.R) << Name(i);
    EXPECT_EQ(state.x_e.p, all.x_e.p) << Name(i);
    EXPECT_EQ(phi.x_e.v, all.x_e.v) << Name(i);
    EXPECT_EQ(phi.Phi, all.Phi) << Name(i);
    // The covariance is symmetric (symmetrised once at the end) and positive definite.
    EXPECT_EQ(all.cov, all.cov.transpose()) << Name(i);
    EXPECT_EQ(Eigen::LLT<Mat15>(all.cov).info(), Eigen::Success) << Name(i);
  }
}

}  // namespace
