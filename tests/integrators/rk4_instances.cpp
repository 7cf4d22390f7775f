// rk4's compiled instances (core/src/kernels/rk4_window.h: the window's integration compiled in
// imuconv_core for the default target and, with GCC on x86-64, for AVX2 + FMA and for AVX-512,
// the widest chosen once) against the portable path (Isa::kPortable, the default-target code),
// on every instance this CPU runs, kBaseline included. The instances are compiled without
// fusing multiply-adds, so vector and scalar code perform the same IEEE operations in the same
// order: the outputs must be bitwise equal (no tolerance), for one step per sample and with
// substeps, and in every output mode (the state must not depend on what else is asked, which is
// what makes montecarlo's mean-only trials the plugin's increments, mean_only.cpp).
#include <gtest/gtest.h>

#include "integrator_cases.h"

namespace {

using namespace imuconv;
using namespace imuconv::test;
using kernels::Isa;

class Rk4Instances : public ::testing::TestWithParam<const char*> {};

TEST_P(Rk4Instances, GiveTheDefaultTargetsOutputsBitwise) {
  const ImuCase c = LoadCase(GetParam());
  const PropagationInput in = MakeInput(c, c.samples[10].t, c.samples[310].t);
  int compared = 0;
  for (Isa isa : {Isa::kPortable, Isa::kBaseline, Isa::kAvx2, Isa::kAvx512}) {
    if (!kernels::IsaAvailable(isa)) continue;
    ++compared;
    for (int substeps : {1, 2}) {
      PropagationResult ref, r;
      ASSERT_TRUE(kernels::PropagateRk4(in, ref, substeps, Isa::kPortable).ok());
      ASSERT_TRUE(kernels::PropagateRk4(in, r, substeps, isa).ok());
      const std::string where =
          std::string("isa ") + kernels::IsaName(isa) + ", substeps " + std::to_string(substeps);
      EXPECT_EQ(r.x_e.R, ref.x_e.R) << where;
      EXPECT_EQ(r.x_e.v, ref.x_e.v) << where;
      EXPECT_EQ(r.x_e.p, ref.x_e.p) << where;
      EXPECT_EQ(r.Phi, ref.Phi) << where;
      EXPECT_EQ(r.cov, ref.cov) << where;
      // The other modes of the instance: the same state and Phi.
      PropagationResult phi_only, state_only;
      kernels::IntegrateRk4<kernels::Outputs::StateAndTransition>(in, phi_only, substeps, isa);
      kernels::IntegrateRk4<kernels::Outputs::State>(in, state_only, substeps, isa);
      EXPECT_EQ(phi_only.Phi, ref.Phi) << where;
      EXPECT_EQ(phi_only.x_e.p, ref.x_e.p) << where;
      EXPECT_EQ(state_only.x_e.R, ref.x_e.R) << where;
      EXPECT_EQ(state_only.x_e.p, ref.x_e.p) << where;
      EXPECT_EQ(state_only.x_e.v, ref.x_e.v) << where;
    }
  }
  EXPECT_GE(compared, 2);  // kPortable and kBaseline run everywhere
}

INSTANTIATE_TEST_SUITE_P(Cases, Rk4Instances, ::testing::Values("smooth-0", "aggressive-0"),
                         CaseTestName);

// Asking for an instance the CPU cannot run is an error, not a crash (SIGILL).
TEST(Rk4Instances, UnavailableInstanceIsAnError) {
  const ImuCase c = LoadCase("smooth-0");
  const PropagationInput in = MakeInput(c, c.samples[0].t, c.samples[20].t);
  int checked = 0;
  for (Isa isa : {Isa::kAvx2, Isa::kAvx512}) {
    if (kernels::IsaAvailable(isa)) continue;
    ++checked;
    PropagationResult r;
    EXPECT_FALSE(kernels::PropagateRk4(in, r, 1, isa).ok());
  }
  if (checked == 0) GTEST_SKIP() << "this CPU runs every instance";
}

}  // namespace
