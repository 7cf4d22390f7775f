// Helpers shared by the integrator tests: the reference cases as kernel input, windows over
// them, and one switch over the three kernels.
#pragma once

#include <string>
#include <vector>

#include "imuconv/kernels/euler.h"
#include "imuconv/kernels/rk4.h"
#include "imuconv/so3.h"
#include "imuconv/window.h"
#include "imuconv_test.h"

namespace imuconv::test {

/// One tests/data/reference/cases/*.json file (FORMAT.md) as kernel input.
struct ImuCase {
  std::vector<ImuSample> samples;
  ImuState x_s;
  Mat15 cov_s_left = Mat15::Zero();
  ImuNoise noise;
  Vec3 gravity = Vec3::Zero();
};

inline ImuCase LoadCase(const std::string& name) {
  const nlohmann::json j = ReadJson(DataPath("reference/cases/" + name + ".json"));
  ImuCase c;
  c.samples = CaseSamples(j);
  const auto& st = j.at("state_s");
  const auto& q = st.at("q_wxyz");
  c.x_s.R = so3::FromQuaternionWxyz(q[0].get<double>(), q[1].get<double>(), q[2].get<double>(),
                                    q[3].get<double>());
  c.x_s.p = JsonVec3(st.at("p"));
  c.x_s.v = JsonVec3(st.at("v"));
  c.x_s.bg = JsonVec3(st.at("bg"));
  c.x_s.ba = JsonVec3(st.at("ba"));
  c.cov_s_left = JsonMatrix(j.at("cov_s_left").at("matrix"));
  const auto& n = j.at("noise");
  c.noise.gyro_noise_density = n.at("gyro_noise_density").get<double>();
  c.noise.accel_noise_density = n.at("accel_noise_density").get<double>();
  c.noise.gyro_random_walk = n.at("gyro_random_walk").get<double>();
  c.noise.accel_random_walk = n.at("accel_random_walk").get<double>();
  c.gravity = JsonVec3(j.at("gravity"));
  return c;
}

/// Kernel input over [t_s, t_e] of a case's samples (which must outlive the input).
inline PropagationInput MakeInput(const ImuCase& c, double t_s, double t_e) {
  PropagationInput in;
  in.x_s = c.x_s;
  in.cov_s = c.cov_s_left;
  in.noise = c.noise;
  in.gravity = c.gravity;
  const Status st = MakeWindow(c.samples.data(), c.samples.size(), t_s, t_e, in.window);
  if (!st.ok()) throw std::runtime_error("MakeWindow: " + st.message());
  return in;
}

enum class Integrator { Euler, Midpoint, Rk4 };

inline const char* Name(Integrator i) {
  switch (i) {
    case Integrator::Euler:
      return "euler";
    case Integrator::Midpoint:
      return "midpoint";
    case Integrator::Rk4:
      return "rk4";
  }
  return "?";
}

const Integrator kIntegrators[] = {Integrator::Euler, Integrator::Midpoint, Integrator::Rk4};

/// The kernel of one integrator, unchecked (inputs of these tests are valid by construction).
template <kernels::Outputs kOut = kernels::Outputs::All>
void RunKernel(Integrator i, const PropagationInput& in, PropagationResult& out,
               int rk4_substeps = 1) {
  switch (i) {
    case Integrator::Euler:
      kernels::IntegrateHeld<kernels::Hold::Euler, kOut>(in, out);
      break;
    case Integrator::Midpoint:
      kernels::IntegrateHeld<kernels::Hold::Midpoint, kOut>(in, out);
      break;
    case Integrator::Rk4:
      kernels::IntegrateRk4<kOut>(in, out, rk4_substeps);
      break;
  }
}

/// The same through the checked entry points the plugins call.
inline Status PropagateKernel(Integrator i, const PropagationInput& in, PropagationResult& out) {
  switch (i) {
    case Integrator::Euler:
      return kernels::PropagateHeld<kernels::Hold::Euler>(in, out);
    case Integrator::Midpoint:
      return kernels::PropagateHeld<kernels::Hold::Midpoint>(in, out);
    case Integrator::Rk4:
      return kernels::PropagateRk4(in, out);
  }
  return Status::Error("unknown integrator");
}

/// A test name from a case name ("smooth-0" -> "smooth_0"; GoogleTest allows no '-').
inline std::string CaseTestName(const ::testing::TestParamInfo<const char*>& info) {
  std::string name = info.param;
  for (char& ch : name)
    if (ch == '-') ch = '_';
  return name;
}

/// max |A - B| / max |B|: the relative change of a matrix.
template <typename A, typename B>
double RelChange(const Eigen::MatrixBase<A>& a, const Eigen::MatrixBase<B>& b) {
  return (a - b).cwiseAbs().maxCoeff() / b.cwiseAbs().maxCoeff();
}

/// A case's measurement noise with the random walks raised (2e-4, 2e-3) so that over 1 s the
/// bias blocks are as large as the start bias uncertainty and resolved by a Monte Carlo (the
/// cases' own are ~100x smaller and would not be tested): monte_carlo.cpp, openvins_methods.cpp.
inline ImuNoise McNoise(const ImuNoise& from_case) {
  ImuNoise n = from_case;
  n.gyro_random_walk = 2e-4;
  n.accel_random_walk = 2e-3;
  return n;
}

/// The Monte Carlo tests' knots: 1 s = 200 steps of `c` (smooth-0 in both), aligned with its
/// samples (samples 200 to 400).
inline std::vector<ImuSample> McKnots(const ImuCase& c) {
  return {c.samples.begin() + 200, c.samples.begin() + 401};
}

/// The fixture of a Monte Carlo test (parameter P) and the nominal propagation it samples
/// around, in_: from smooth-0's start state over all of McKnots, knots_ (in_'s window points
/// into them, so the fixture keeps them for the whole test), with McNoise and smooth-0's
/// gravity; in_.cov_s is zero.
template <class P>
class McNominalTest : public ::testing::TestWithParam<P> {
 protected:
  void SetUp() override {
    in_.x_s = case_.x_s;
    in_.noise = McNoise(case_.noise);
    in_.gravity = case_.gravity;
    ASSERT_TRUE(
        MakeWindow(knots_.data(), knots_.size(), knots_.front().t, knots_.back().t, in_.window)
            .ok());
  }
  const ImuCase case_ = LoadCase("smooth-0");
  const std::vector<ImuSample> knots_ = McKnots(case_);
  PropagationInput in_;
};

}  // namespace imuconv::test
