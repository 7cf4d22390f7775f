// `orb_slam3`: ORB-SLAM3's EdgeInertial (UZ-SLAMLab/ORB_SLAM3, src/G2oTypes.cc: its
// constructor's information, computeError, linearizeOplus) as a residual plugin: the 9-dim
// residual [er, ev, ep] between (pose 1, velocity 1, biases 1) and (pose 2, velocity 2), its
// information (C[0:9] inverted in double, symmetrized, eigenvalues below 1e-12 set to 0; not
// written when C[0:9] does not invert, e.g. without noise), chi2 = r^T information r (the
// squared distance), and the six Jacobians of linearizeOplus w.r.t. g2o's vertex updates:
// VertexPose [dtheta, dt] (R Exp(dtheta), t + R dt: body-frame), VertexVelocity, VertexGyroBias,
// VertexAccBias (additive). The biases of x_s enter as EdgeInertial reads them: into IMU::Bias,
// in float, and the deltas follow to first order from the measurement's linearization bias
// (GetDelta*). ORB-SLAM3 holds its preintegration in float: the measurement (expressed in
// `orb_slam3`, [theta, v, p, bg, ba], J_bias [[JRg, 0], [JVg, JVa], [JPg, JPa]]) is read back
// into float here; from the `orb_slam3` preintegrator those are its own floats, widened and
// narrowed exactly but for the round trip through the reference chart (about 1e-16 relative).
// The kernel is core/include/imuconv/kernels/orb_slam3.h; it agrees with ORB-SLAM3's own
// numbers on the ten reference cases (tests/reference/orb_slam3_anchor.cpp).
#include <cmath>

#include "imuconv/kernels/orb_slam3.h"
#include "imuconv/plugin/residual_plugin.h"
#include "imuconv/plugin_abi.h"
#include "jacobian_blocks.h"

namespace {

using namespace imuconv;
namespace k = imuconv::kernels;

/// IMU::Preintegrated from a measurement expressed in `orb_slam3`, in float as upstream holds
/// it (only what EdgeInertial reads: the bias, dT, the deltas, their bias Jacobians and C).
k::OrbSlam3Preintegrated OrbSlam3PreintegratedOf(const Preintegrated& m) {
  k::OrbSlam3Preintegrated p;
  p.b = k::OrbSlam3Bias{m.bg_hat.cast<float>(), m.ba_hat.cast<float>()};
  p.dT = static_cast<float>(m.dt);
  p.dR = m.delta.dR.cast<float>();
  p.dV = m.delta.dv.cast<float>();
  p.dP = m.delta.dp.cast<float>();
  p.JRg = m.J_bias.block<3, 3>(0, 0).cast<float>();
  p.JVg = m.J_bias.block<3, 3>(3, 0).cast<float>();
  p.JVa = m.J_bias.block<3, 3>(3, 3).cast<float>();
  p.JPg = m.J_bias.block<3, 3>(6, 0).cast<float>();
  p.JPa = m.J_bias.block<3, 3>(6, 3).cast<float>();
  p.C = m.cov.cast<float>();
  return p;
}

constexpr auto* OrbSlam3PoseOf = &plugin::PoseVelOf<k::OrbSlam3Pose<double>>;

struct OrbSlam3Factor {
  static constexpr const char* kIncrementConvention = "orb_slam3";
  static constexpr const char* kLayout =
      "ORB-SLAM3 EdgeInertial (G2oTypes.cc): residual [er, ev, ep] = [Log(dR(b1)^T R1^T R2), "
      "R1^T (v2 - v1 - g dT) - dV(b1), R1^T (p2 - p1 - v1 dT - g dT^2/2) - dP(b1)], the deltas "
      "first-order at the biases b1 = x_s's read in float (GetDelta*); information 9x9 "
      "[er, ev, ep] (C[0:9] inverted in double, symmetrized, eigenvalues < 1e-12 set to 0); chi2 "
      "= r^T information r, written as mahalanobis_squared; J_pose1, J_pose2 9x6 w.r.t. VertexPose "
      "[dtheta, dt] (R Exp(dtheta), "
      "t + R dt), J_vel1, J_vel2 9x3 (v + dv), J_gyro_bias1, J_acc_bias1 9x3 (b + db); pose 1 = "
      "x_s, pose 2 = x_e; the measurement expressed in orb_slam3 and read in float; g = (0, 0, "
      "-9.81f) (IMU::GRAVITY_VALUE)";
  static constexpr int kDegreesOfFreedom = 9;
  // As a cost (residual_cost_spec.h): 9 rows, no bias-walk rows (EdgeGyroRW and EdgeAccRW are
  // separate edges in ORB-SLAM3), whitened by a square root of the information. VertexPose
  // moves R Exp(dtheta), t + R dt, and velocity and biases additively: the chart of `forster`
  // (R Exp(dtheta), p + R dp, v + dv, b + db); the end state's biases do not enter.
  static constexpr ResidualCostSpec kCostSpec =
      plugin::CostSpecOf("residual", "forster", ResidualWeighting::Information, "information",
                         {{"J_pose1", Block::theta, Block::p},
                          {"J_vel1", Block::v},
                          {"J_gyro_bias1", Block::bg},
                          {"J_acc_bias1", Block::ba}},
                         {{"J_pose2", Block::theta, Block::p}, {"J_vel2", Block::v}});

  Status operator()(const Preintegrated& m, const ImuState& x_s, const ImuState& x_e,
                    const Vec3& gravity, ResidualSink& sink) const {
    // EdgeInertial's gravity is IMU::GRAVITY_VALUE = 9.81f along -z (ORB-SLAM3 turns its world
    // by Rwg instead); 1e-6 m/s^2 admits the double 9.81 and the float 9.81f alike.
    if (gravity.x() != 0.0 || gravity.y() != 0.0 || !(std::abs(gravity.z() + 9.81) <= 1e-6))
      return Status::Error(
          "orb_slam3: EdgeInertial's gravity is (0, 0, -9.81) (IMU::GRAVITY_VALUE); give that "
          "gravity");
    const k::OrbSlam3Preintegrated pre = OrbSlam3PreintegratedOf(m);
    if (!pre.dR.allFinite() || !pre.dV.allFinite() || !pre.dP.allFinite() || !pre.C.allFinite() ||
        !std::isfinite(pre.dT) || !pre.b.bg.allFinite() || !pre.b.ba.allFinite())
      return Status::Error("orb_slam3: the measurement does not fit in float (ORB-SLAM3's)");
    const k::OrbSlam3EdgeInertial e = k::EvaluateOrbSlam3EdgeInertial(
        pre, OrbSlam3PoseOf(x_s), x_s.bg, x_s.ba, OrbSlam3PoseOf(x_e));
    // A measurement without noise (zero densities) has no information: C[0:9] does not invert.
    // Then only the residual and the Jacobians are written.
    const bool weighted = e.information.allFinite() && std::isfinite(e.chi2);
    if (weighted) WriteMatrix(sink, "information", e.information);
    WriteVector(sink, "residual", e.residual);
    WriteMatrix(sink, "J_pose1", e.J_pose1);
    WriteMatrix(sink, "J_vel1", e.J_vel1);
    WriteMatrix(sink, "J_gyro_bias1", e.J_gyro_bias1);
    WriteMatrix(sink, "J_acc_bias1", e.J_acc_bias1);
    WriteMatrix(sink, "J_pose2", e.J_pose2);
    WriteMatrix(sink, "J_vel2", e.J_vel2);
    if (weighted) sink.mahalanobis_squared(e.chi2);
    return Status::Ok();
  }
};

}  // namespace

IMUCONV_PLUGIN(Residual, imuconv::plugin::KernelResidual<OrbSlam3Factor>, "orb_slam3", "1.0.0",
               "ORB-SLAM3 EdgeInertial: 9-dim [er, ev, ep], information, chi2 and six Jacobians "
               "(float preintegration)")
