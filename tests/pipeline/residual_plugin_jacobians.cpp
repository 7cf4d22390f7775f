// Central differences of the analytic Jacobians that the `okvis2` and `orb_slam3` residual
// plugins write (plugins/residuals/), called through the registry as the residual task calls
// them: each column is (r(x + h e_k) - r(x - h e_k)) / 2h along the system's own parameter
// increment, as its layout states it:
//  - OKVIS2's minimal pose Jacobians: r + dr, C = Exp(dalpha) C (PoseManifold::plus, world);
//    its speed-and-bias Jacobians: v, bg, ba additive;
//  - ORB-SLAM3's VertexPose [dtheta, dt]: R Exp(dtheta), p + R dt (body frame); velocity and
//    biases additive.
// The measurement: the plugin's own preintegrator (`okvis2`, `orb_slam3`) over the first
// second of reference case smooth-0, at the case's bias; the start state the case's, the
// end state the measurement's prediction moved by a small error, so every row is nonzero.
// The start biases are the measurement's linearization bias: there both systems' bias
// Jacobians are exact derivatives (away from it they are each system's first-order model,
// which the anchors test as coded).
//
// Tolerances. OKVIS2 computes in double: with h = 1e-6 the differences' truncation error is
// about h^2 |r'''| (< 1e-10 here: residual terms of a few metres over one second) and their
// rounding about eps |r| / h (< 1e-9): 1e-7 of the Jacobian's largest entry (at least 1) is
// 100x above both and far below any wrong block (O(1) of an entry). ORB-SLAM3 evaluates its
// edge in double from float deltas; its pose and velocity columns are double arithmetic (the
// same 1e-7). Its bias columns go through IMU::Bias in float and float first-order deltas
// (6e-8 of |dV|, |dP|, a few m/s and m here): with h = 1e-2 that rounding is about 6e-8 x 5 /
// 2e-2 = 1.5e-5 of an entry, and the one nonlinear row (the rotation's Exp(JRg dbg)) has a
// truncation error near h^2 |JRg|^3 = 1e-4 for |JRg| of about 1 over one second: those
// columns are held to 1e-3 of the Jacobian's largest entry, 10x above that, still far below a
// wrong sign or block.
#include <gtest/gtest.h>

#include <functional>
#include <map>
#include <string>
#include <vector>

#include "imuconv/registry.h"
#include "imuconv/residual_factor.h"
#include "imuconv/so3.h"
#include "imuconv_test.h"
#include "keeping_residual_sink.h"
#include "reference_case.h"

namespace {
using namespace imuconv;
using namespace imuconv::test;

struct FactorSetup {
  Preintegrated m;
  ImuState x_s, x_e;
  Vec3 gravity;
};

/// The first second of smooth-0 preintegrated by `preintegrator` (in its own charts, the
/// residual plugin's convention), and two states around its prediction.
FactorSetup MakeFactorSetup(const std::string& preintegrator) {
  const nlohmann::json c = ReadJson(DataPath("reference/cases/smooth-0.json"));
  const std::vector<ImuSample> all = CaseSamples(c);
  const std::vector<ImuSample> samples(all.begin(), all.begin() + 201);
  FactorSetup s;
  s.gravity = JsonVec3(c.at("gravity"));
  const nlohmann::json& st = c.at("state_s");
  const nlohmann::json& q = st.at("q_wxyz");
  s.x_s.R = Eigen::Quaterniond(q[0], q[1], q[2], q[3]).normalized().toRotationMatrix();
  s.x_s.p = JsonVec3(st.at("p"));
  s.x_s.v = JsonVec3(st.at("v"));
  s.x_s.bg = JsonVec3(st.at("bg"));
  s.x_s.ba = JsonVec3(st.at("ba"));
  PreintegrationInput in;
  in.bg = s.x_s.bg;
  in.ba = s.x_s.ba;
  in.noise = CaseNoise(c);
  EXPECT_TRUE(
      MakeWindow(samples.data(), samples.size(), samples.front().t, samples.back().t, in.window)
          .ok());
  EXPECT_TRUE(Plugins().preintegrator(preintegrator)->integrate(in, s.m).ok());
  const double T = s.m.dt;
  s.x_e.R = s.x_s.R * s.m.delta.dR * so3::Exp(Vec3(0.01, -0.02, 0.015));
  s.x_e.p = s.x_s.p + s.x_s.v * T + 0.5 * s.gravity * T * T + s.x_s.R * s.m.delta.dp +
            Vec3(0.03, -0.01, 0.02);
  s.x_e.v = s.x_s.v + s.gravity * T + s.x_s.R * s.m.delta.dv + Vec3(-0.02, 0.01, 0.03);
  s.x_e.bg = s.x_s.bg + Vec3(1e-4, -2e-4, 3e-4);
  s.x_e.ba = s.x_s.ba + Vec3(-1e-3, 2e-3, 1e-3);
  return s;
}

std::map<std::string, Eigen::MatrixXd> EvaluateFactor(const std::string& id, const FactorSetup& s,
                                                      const ImuState& x_s, const ImuState& x_e) {
  KeepingResidualSink sink;
  const Status st = Plugins().residual_factor(id)->evaluate(s.m, x_s, x_e, s.gravity, sink);
  EXPECT_TRUE(st.ok()) << st.message();
  return sink.values;
}

/// One parameter block: how a perturbation d (of the block's size) moves a state.
using FactorPerturb = std::function<void(ImuState&, const Eigen::VectorXd&)>;

/// Central differences of `residual` along `perturb` of the start (`start` true) or end state.
Eigen::MatrixXd NumericJacobian(const std::string& id, const FactorSetup& s, const char* residual,
                                bool start, int cols, const FactorPerturb& perturb, double h) {
  const int rows = static_cast<int>(EvaluateFactor(id, s, s.x_s, s.x_e).at(residual).size());
  Eigen::MatrixXd J(rows, cols);
  for (int k = 0; k < cols; ++k) {
    Eigen::VectorXd d = Eigen::VectorXd::Zero(cols);
    d[k] = h;
    ImuState plus_s = s.x_s, plus_e = s.x_e, minus_s = s.x_s, minus_e = s.x_e;
    perturb(start ? plus_s : plus_e, d);
    perturb(start ? minus_s : minus_e, -d);
    J.col(k) = (EvaluateFactor(id, s, plus_s, plus_e).at(residual) -
                EvaluateFactor(id, s, minus_s, minus_e).at(residual)) /
               (2.0 * h);
  }
  return J;
}

/// max |analytic - numeric| over the largest entry of the analytic Jacobian (at least 1).
double JacobianRelativeError(const Eigen::MatrixXd& analytic, const Eigen::MatrixXd& numeric) {
  return (analytic - numeric).cwiseAbs().maxCoeff() / std::max(1.0, analytic.cwiseAbs().maxCoeff());
}

const FactorPerturb kWorldPoseLeft = [](ImuState& x, const Eigen::VectorXd& d) {
  x.p += d.head<3>();
  x.R = so3::Exp(d.tail<3>()) * x.R;
};
const FactorPerturb kSpeedBias = [](ImuState& x, const Eigen::VectorXd& d) {
  x.v += d.segment<3>(0);
  x.bg += d.segment<3>(3);
  x.ba += d.segment<3>(6);
};
const FactorPerturb kBodyPoseRight = [](ImuState& x, const Eigen::VectorXd& d) {
  const Mat3 R = x.R;
  x.R = R * so3::Exp(d.head<3>());
  x.p += R * d.tail<3>();
};
const FactorPerturb kVelocity = [](ImuState& x, const Eigen::VectorXd& d) { x.v += d; };
const FactorPerturb kGyroBias = [](ImuState& x, const Eigen::VectorXd& d) { x.bg += d; };
const FactorPerturb kAccBias = [](ImuState& x, const Eigen::VectorXd& d) { x.ba += d; };

TEST(ResidualPluginJacobians, Okvis2MinimalAndSpeedBiasJacobiansAreCentralDifferences) {
  const FactorSetup s = MakeFactorSetup("okvis2");
  const auto a = EvaluateFactor("okvis2", s, s.x_s, s.x_e);
  ASSERT_GT(a.at("raw/residual").norm(), 1e-3);  // the states are not the prediction
  constexpr double h = 1e-6, tol = 1e-7;
  struct JacobianBlock {
    const char* jacobian;
    bool start;
    int cols;
    const FactorPerturb& perturb;
  };
  for (const JacobianBlock& b :
       {JacobianBlock{"raw/jacobian_pose_0_minimal", true, 6, kWorldPoseLeft},
        JacobianBlock{"raw/jacobian_speedbias_0", true, 9, kSpeedBias},
        JacobianBlock{"raw/jacobian_pose_1_minimal", false, 6, kWorldPoseLeft},
        JacobianBlock{"raw/jacobian_speedbias_1", false, 9, kSpeedBias}}) {
    const Eigen::MatrixXd numeric =
        NumericJacobian("okvis2", s, "raw/residual", b.start, b.cols, b.perturb, h);
    const double e = JacobianRelativeError(a.at(b.jacobian), numeric);
    std::printf("  okvis2 %-26s %.2g\n", b.jacobian, e);
    EXPECT_LE(e, tol) << b.jacobian << "\nanalytic\n"
                      << a.at(b.jacobian) << "\nnumeric\n"
                      << numeric;
  }
}

TEST(ResidualPluginJacobians, OrbSlam3EdgeInertialJacobiansAreCentralDifferences) {
  const FactorSetup s = MakeFactorSetup("orb_slam3");
  const auto a = EvaluateFactor("orb_slam3", s, s.x_s, s.x_e);
  ASSERT_GT(a.at("residual").norm(), 1e-3);
  struct JacobianBlock {
    const char* jacobian;
    bool start;
    int cols;
    const FactorPerturb& perturb;
    double h, tol;  // header: double columns, and the bias columns read in float
  };
  for (const JacobianBlock& b : {JacobianBlock{"J_pose1", true, 6, kBodyPoseRight, 1e-6, 1e-7},
                                 JacobianBlock{"J_vel1", true, 3, kVelocity, 1e-6, 1e-7},
                                 JacobianBlock{"J_gyro_bias1", true, 3, kGyroBias, 1e-2, 1e-3},
                                 JacobianBlock{"J_acc_bias1", true, 3, kAccBias, 1e-2, 1e-3},
                                 JacobianBlock{"J_pose2", false, 6, kBodyPoseRight, 1e-6, 1e-7},
                                 JacobianBlock{"J_vel2", false, 3, kVelocity, 1e-6, 1e-7}}) {
    const Eigen::MatrixXd numeric =
        NumericJacobian("orb_slam3", s, "residual", b.start, b.cols, b.perturb, b.h);
    const double e = JacobianRelativeError(a.at(b.jacobian), numeric);
    std::printf("  orb_slam3 %-14s %.2g\n", b.jacobian, e);
    EXPECT_LE(e, b.tol) << b.jacobian << "\nanalytic\n"
                        << a.at(b.jacobian) << "\nnumeric\n"
                        << numeric;
  }
}

}  // namespace
