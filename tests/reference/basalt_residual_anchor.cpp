// Basalt's IMU residual against its own numbers (tests/data/reference/anchors/basalt,
// README.md there): IntegratedImuMeasurement::residual() with its four Jacobians on each of
// the ten reference cases and both feedings, at the linearization bias and at a changed
// bias, and the first-order bias correction, against kernels/basalt_residual.h on imuconv's
// own delta state (kernels/basalt.h, reproduced in basalt_anchor.cpp). The residual's inputs
// (state0, state1, curr_*) are the anchor's own.
//
// Tolerance: anchors.h's 1e-8 by the note's metric on every field: the same formulas on a
// delta state that agrees to round-off (rotation matrices here, Sophus quaternions upstream).
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "anchors.h"
#include "imuconv/kernels/basalt.h"
#include "imuconv/kernels/basalt_residual.h"
#include "imuconv/so3.h"
#include "imuconv_test.h"

namespace {

using namespace imuconv;
using namespace imuconv::kernels;
using namespace imuconv::test;  // DataPath, JsonMatrix, MaxEntryDiff, the anchors' bounds

/// The anchor's two feedings: its key and the kernel's feeding.
struct ResidualFeeding {
  const char* key;
  BasaltFeeding feeding;
};
const ResidualFeeding kResidualFeedings[] = {{"native", BasaltFeeding::kNative},
                                             {"forward_zoh", BasaltFeeding::kForwardZoh}};

BasaltPoseVelState PoseVel(const nlohmann::json& s) {
  BasaltPoseVelState x;
  x.R = JsonMatrix(s.at("R"));
  x.p = JsonVec3(s.at("p"));
  x.v = JsonVec3(s.at("v"));
  return x;
}

class BasaltResidualAnchor : public AnchorCaseTest {
 protected:
  BasaltResidualAnchor() : AnchorCaseTest("basalt") {}
  void SetUp() override {
    variances_.accel = JsonVec3(inputs_.at("accel_cov"));
    variances_.gyro = JsonVec3(inputs_.at("gyro_cov"));
    g_ = JsonVec3(inputs_.at("g"));
    ASSERT_EQ(g_, case_.gravity);
  }
  /// The measurement of one feeding at the case's start biases.
  BasaltMeasurement Measure(BasaltFeeding feeding) const {
    BasaltMeasurement m;
    m.bias_gyro_lin = case_.x_s.bg;
    m.bias_accel_lin = case_.x_s.ba;
    EXPECT_TRUE(
        IntegrateBasalt(AnchorInput(case_, case_.x_s.bg, case_.x_s.ba), feeding, variances_, m.pre)
            .ok());
    return m;
  }
  /// One evaluation the anchor's "factor" records: a feeding's measurement and two states, at
  /// the linearization biases (`lin`) or the changed ones, and imuconv's residual there.
  struct FactorPoint {
    const ResidualFeeding& feed;
    bool lin;
    const nlohmann::json& factor;
    const BasaltMeasurement& m;
    BasaltPoseVelState x0, x1;
    Vec3 bg, ba;
    BasaltResidual r;
  };
  /// Calls check(point) for each feeding, at the linearization biases and then the new ones.
  template <typename Check>
  void ForEachFactorPoint(Check check) const {
    for (const ResidualFeeding& feed : kResidualFeedings) {
      const nlohmann::json& f = anchor_.at(feed.key).at("factor");
      const BasaltMeasurement m = Measure(feed.feeding);
      const BasaltPoseVelState x0 = PoseVel(f.at("state0")), x1 = PoseVel(f.at("state1"));
      for (const bool lin : {true, false}) {
        const Vec3 bg = JsonVec3(f.at(lin ? "curr_bg" : "curr_bg_new")),
                   ba = JsonVec3(f.at(lin ? "curr_ba" : "curr_ba_new"));
        check(
            FactorPoint{feed, lin, f, m, x0, x1, bg, ba, BasaltResidualOf(m, x0, g_, x1, bg, ba)});
      }
    }
  }
  BasaltSampleVariances variances_;
  Vec3 g_;
};

TEST_P(BasaltResidualAnchor, ResidualAndJacobiansAreBasaltOwn) {
  ForEachFactorPoint([&](const FactorPoint& p) {
    const char* at = p.lin ? "at_lin_bias" : "at_new_bias";
    const BasaltResidual& r = p.r;
    const nlohmann::json& a = p.factor.at(at);
    const double d_r = MaxEntryDiff(JsonMatrix(a.at("residual")), r.residual);
    const double d_0 = MaxEntryDiff(JsonMatrix(a.at("d_res_d_state0")), r.d_res_d_state0);
    const double d_1 = MaxEntryDiff(JsonMatrix(a.at("d_res_d_state1")), r.d_res_d_state1);
    const double d_bg = MaxEntryDiff(JsonMatrix(a.at("d_res_d_bg")), r.d_res_d_bg);
    const double d_ba = MaxEntryDiff(JsonMatrix(a.at("d_res_d_ba")), r.d_res_d_ba);
    const std::string label = std::string(GetParam()) + " " + p.feed.key + " " + at;
    std::printf("  %-36s residual %.2g d_state0 %.2g d_state1 %.2g d_bg %.2g d_ba %.2g\n",
                label.c_str(), d_r, d_0, d_1, d_bg, d_ba);
    for (const double d : {d_r, d_0, d_1, d_bg, d_ba}) EXPECT_LE(d, kAnchorMetricTol) << label;
  });
}

TEST_P(BasaltResidualAnchor, FirstOrderBiasCorrectionIsBasaltOwn) {
  for (const ResidualFeeding& feed : kResidualFeedings) {
    const nlohmann::json& bc = anchor_.at(feed.key).at("bias_correction");
    const BasaltMeasurement m = Measure(feed.feeding);
    const BasaltPoseVelState c =
        BasaltCorrectedDelta(m, JsonVec3(bc.at("bg_new")), JsonVec3(bc.at("ba_new")));
    const nlohmann::json& fo = bc.at("first_order");
    const double d_R = MaxEntryDiff(JsonMatrix(fo.at("R")), c.R);
    const double d_p = MaxEntryDiff(JsonMatrix(fo.at("p")), c.p);
    const double d_v = MaxEntryDiff(JsonMatrix(fo.at("v")), c.v);
    std::printf("  %-26s first_order R %.2g p %.2g v %.2g\n",
                (std::string(GetParam()) + " " + feed.key).c_str(), d_R, d_p, d_v);
    for (const double d : {d_R, d_p, d_v}) EXPECT_LE(d, kAnchorMetricTol);
  }
}

// The Jacobians against central differences of residual() through applyInc (states) and
// additive bias steps.
//
// Tolerance. Step h = 1e-6. The residual's terms reach |g T^2/2| = 490 m (T = 10 s), so
// rounding alone gives about 2.2e-16 x 490 / (2 h) = 5e-8 per entry; the truncation
// h^2/6 |r'''| is below 1e-9. Bound 1e-6 absolute, measured below (the anchors README
// reports upstream's own agreement as <= 1.2e-7).
constexpr double kBasaltFdStep = 1e-6;
constexpr double kBasaltFdTol = 1e-6;

struct Numeric {
  Mat9 d_state0, d_state1;
  Mat93 d_bg, d_ba;
};

Numeric NumericJacobians(const BasaltMeasurement& m, const BasaltPoseVelState& x0, const Vec3& g,
                         const BasaltPoseVelState& x1, const Vec3& bg, const Vec3& ba) {
  Numeric n;
  for (int k = 0; k < 9; ++k) {
    Vec9 d = Vec9::Zero();
    d[k] = kBasaltFdStep;
    n.d_state0.col(k) = (BasaltResidualOf(m, BasaltApplyInc(x0, d), g, x1, bg, ba).residual -
                         BasaltResidualOf(m, BasaltApplyInc(x0, -d), g, x1, bg, ba).residual) /
                        (2 * kBasaltFdStep);
    n.d_state1.col(k) = (BasaltResidualOf(m, x0, g, BasaltApplyInc(x1, d), bg, ba).residual -
                         BasaltResidualOf(m, x0, g, BasaltApplyInc(x1, -d), bg, ba).residual) /
                        (2 * kBasaltFdStep);
  }
  for (int k = 0; k < 3; ++k) {
    const Vec3 d = kBasaltFdStep * Vec3::Unit(k);
    n.d_bg.col(k) = (BasaltResidualOf(m, x0, g, x1, bg + d, ba).residual -
                     BasaltResidualOf(m, x0, g, x1, bg - d, ba).residual) /
                    (2 * kBasaltFdStep);
    n.d_ba.col(k) = (BasaltResidualOf(m, x0, g, x1, bg, ba + d).residual -
                     BasaltResidualOf(m, x0, g, x1, bg, ba - d).residual) /
                    (2 * kBasaltFdStep);
  }
  return n;
}

// At the linearization bias every Jacobian is an exact derivative. At the new bias all are
// but the theta rows of d r / d bg: upstream's Jl^-1(r_theta) J_bg,theta omits the factor
// Jl(phi), phi = J_bg,theta dbg, of the derivative of Exp(phi) (basalt_residual.h). With that
// factor put back the block is held to the FD bound, so the approximation is exactly the
// one named; upstream's own block is printed beside it.
TEST_P(BasaltResidualAnchor, JacobiansAreCentralDifferencesThroughApplyInc) {
  ForEachFactorPoint([&](const FactorPoint& p) {
    const BasaltMeasurement& m = p.m;
    const BasaltResidual& r = p.r;
    const bool lin = p.lin;
    const Vec3& bg = p.bg;
    const Numeric n = NumericJacobians(m, p.x0, g_, p.x1, bg, p.ba);
    Mat93 d_bg = r.d_res_d_bg;
    const Vec3 phi = m.pre.d_state_d_bg.middleRows<3>(3) * (bg - m.bias_gyro_lin);
    const Vec3 r_theta = r.residual.segment<3>(3);
    const double upstream_bg = (n.d_bg - d_bg).cwiseAbs().maxCoeff();
    d_bg.middleRows<3>(3) =
        so3::JlInv(r_theta) * so3::Jl(phi) * m.pre.d_state_d_bg.middleRows<3>(3);
    const double worst = std::max({(n.d_state0 - r.d_res_d_state0).cwiseAbs().maxCoeff(),
                                   (n.d_state1 - r.d_res_d_state1).cwiseAbs().maxCoeff(),
                                   (n.d_ba - r.d_res_d_ba).cwiseAbs().maxCoeff(),
                                   (n.d_bg - d_bg).cwiseAbs().maxCoeff()});
    std::printf(
        "  %-13s %-11s %s: FD %.2g abs | upstream's d_res_d_bg %.2g abs (|phi| = %.2g, max "
        "|d_res_d_bg| %.2g)\n",
        GetParam(), p.feed.key, lin ? "lin bias" : "new bias", worst, upstream_bg, phi.norm(),
        r.d_res_d_bg.cwiseAbs().maxCoeff());
    EXPECT_LE(worst, kBasaltFdTol);
    if (lin) {
      EXPECT_LE(upstream_bg, kBasaltFdTol);  // phi = 0: upstream's block is the derivative
    }
  });
}

INSTANTIATE_TEST_SUITE_P(Reference, BasaltResidualAnchor, ::testing::ValuesIn(kReferenceCaseIds),
                         CaseTestName);

}  // namespace
