// The rk4 kernel (Magnus rotation, quadratures at the nodes 0, h/2, h, covariance by variation
// of constants, core/include/imuconv/kernels/rk4.h) against the classical RK4 of state, Phi and
// covariance it replaced (rk4_reference.h). Both are fourth order with different error
// constants, so they must agree to O(h^4): small, and ~16x smaller per halving of the step.
// This checks the derivation (signs, Psi's columns, M's blocks, Phi = Psi^{-1}) independently
// of the convergence test, which only sees the kernel against itself; the reference shares no
// kernel code, its noise variances included.
#include <gtest/gtest.h>

#include <iostream>
#include <string>

#include "integrator_cases.h"
#include "rk4_reference.h"

namespace {

using namespace imuconv;
using namespace imuconv::test;
namespace li = imuconv::left_idx;

struct CrossCheckDifference {
  double state, phi, cov;
};

CrossCheckDifference KernelVsReference(const PropagationInput& in, int substeps) {
  PropagationResult a, b;
  kernels::IntegrateRk4<kernels::Outputs::All>(in, a, substeps);
  rk4_reference::IntegrateRk4(in, b, substeps);
  Vec15 d;
  LeftLocal(b.x_e, a.x_e, d);
  return {d.cwiseAbs().maxCoeff(), RelChange(a.Phi, b.Phi), RelChange(a.cov, b.cov)};
}

class Rk4VsClassicalRk4 : public ::testing::TestWithParam<const char*> {};

// 2 s (400 knot intervals) of each case, with the start covariance of the case.
TEST_P(Rk4VsClassicalRk4, AgreeToFourthOrder) {
  const ImuCase c = LoadCase(GetParam());
  const PropagationInput in = MakeInput(c, c.samples.front().t, c.samples[400].t);
  const CrossCheckDifference one = KernelVsReference(in, 1), two = KernelVsReference(in, 2);
  std::cout << "[ measured ] rk4 vs classical RK4 on " << GetParam() << " (2 s), 1 substep: state "
            << one.state << ", Phi " << one.phi << ", cov " << one.cov
            << "; ratio to 2 substeps: " << one.state / two.state << ", " << one.phi / two.phi
            << ", " << one.cov / two.cov << "\n";
  // Measured at 200 Hz: at most 3.0e-7 (state, aggressive-0 at up to 6 rad/s), 4.4e-8 (Phi),
  // 8.4e-9 (cov); the bounds leave ~3x room.
  EXPECT_LT(one.state, 1e-6);
  EXPECT_LT(one.phi, 1.5e-7);
  EXPECT_LT(one.cov, 3e-8);
  // Both fourth order: the difference shrinks by 2^4 per halving ([12, 20] as in
  // rk4_convergence.cpp; it is well above rounding here, >= 5e-13).
  for (double ratio : {one.state / two.state, one.phi / two.phi, one.cov / two.cov}) {
    EXPECT_GT(ratio, 12.0);
    EXPECT_LT(ratio, 20.0);
  }
}

INSTANTIATE_TEST_SUITE_P(Cases, Rk4VsClassicalRk4,
                         ::testing::Values("smooth-0", "aggressive-0", "jitter-0"),
                         [](const ::testing::TestParamInfo<const char*>& info) {
                           std::string name = info.param;
                           for (char& ch : name)
                             if (ch == '-') ch = '_';
                           return name;
                         });

// The once-per-window congruence in block form (left_transition.h; rk4, euler and midpoint
// use it) against the dense 15x15 product.
TEST(LeftTransitionAlgebra, CongruenceMatchesDense) {
  kernels::LeftTransition T;
  for (Mat3* m : {&T.th_bg, &T.v_th, &T.v_bg, &T.v_ba, &T.p_th, &T.p_bg, &T.p_ba})
    *m = Mat3::Random();
  T.p_v = 0.7;
  const Mat15 L = Mat15::Random(), P = L * L.transpose();
  const Mat15 dense = T.ToMatrix() * P * T.ToMatrix().transpose();
  EXPECT_LT(RelChange(kernels::Congruence(T, P), dense), 1e-14);  // rounding only
}

}  // namespace
