// The residual task's kind "orb_slam3" (plugins/residuals/orb_slam3.cpp) against ORB-SLAM3's
// own EdgeInertial (tests/data/reference/anchors/orb-slam3, README.md there): a pipeline over
// a whole reference case preintegrates it with the `orb_slam3` preintegrator at the anchor's
// linearization bias, and two residual tasks with the anchor's own vertices give the edge at
// that bias (`at_lin_bias`, state_i) and at the new bias (`at_new_bias`, state_i_new_bias:
// the deltas first-order from the same measurement, as EdgeInertial's GetDelta* do). The path
// is the pipeline's: the measurement goes through the registry (native float results widened,
// reference charts, expressed in `orb_slam3`, read back into float by the plugin), the states
// through the pipeline's state form.
//
// Tolerance: the 1e-4 by the note's metric for a single-precision original, on every
// field (tests/reference/orb_slam3_anchor.cpp says why; the kernel there agrees to 4.7e-11 on
// the edge). Here the measurement also takes the pipeline's times (relative to an origin,
// through nanoseconds) and a round trip through the reference chart before it is read back
// into float (about 1e-16 relative, below float's half-ulp except on a tie), so the float
// deltas are the original's or one float ulp (6e-8 relative) away: inside 1e-4. The same
// x86-64 condition as orb_slam3_anchor.cpp: elsewhere Eigen's packet math fuses multiply-adds
// in the float preintegration and there is no original's number to compare with.
#include <gtest/gtest.h>

#include <string>

#include "../reference/anchor_field_diffs.h"
#include "../reference/anchors.h"
#include "imuconv/pipeline/pipeline.h"
#include "imuconv_test.h"
#include "pipeline_test_util.h"
#include "residual_over_case.h"

namespace {
using namespace imuconv;
using namespace imuconv::test;
using nlohmann::json;

constexpr double kOrbFloatTol = 1e-4;

class ResidualOrbSlam3 : public ::testing::TestWithParam<const char*> {};

TEST_P(ResidualOrbSlam3, KindOrbSlam3WritesEdgeInertialAsOrbSlam3Does) {
#if !defined(__x86_64__)
  GTEST_SKIP() << "EdgeInertial is compared where the original's float arithmetic is "
                  "reproduced (x86-64; tests/reference/orb_slam3_anchor.cpp)";
#endif
  const std::string id = GetParam();
  const json c = ReadJson(DataPath("reference/cases/" + id + ".json"));
  const json ej =
      ReadJson(DataPath("reference/anchors/orb-slam3/" + id + ".json")).at("edge_inertial");
  const double t0 = c.at("imu").front().at(0), t1 = c.at("imu").back().at(0);
  const json& si = ej.at("state_i");
  auto residual = [&](const char* name, const json& start) {
    return ResidualTask(name, "orb_slam3", "pre", AnchorStateJson(start),
                        AnchorStateJson(ej.at("state_j")));
  };
  const json out =
      RunOverCase(c,
                  {PreintegrateTask("pre", "orb_slam3", si, t0, t1), residual("at_lin", si),
                   residual("at_new", ej.at("state_i_new_bias"))},
                  id + " (in memory)");
  // The measurement's dT is ORB-SLAM3's float sum of its float steps.
  EXPECT_EQ(
      static_cast<float>(TaskOutput(out, "pre").at("measurements").at(0).at("dt").get<double>()),
      static_cast<float>(ej.at("dt").get<double>()));
  AnchorFieldDiffs w(id + " orb_slam3 residual task", kOrbFloatTol);
  // EdgeInertial inverts C[0:9] as ORB-SLAM3's float arithmetic left it, not quite symmetric
  // (C_ij and C_ji of its small cross terms differ by up to 6 % on these cases). A measurement
  // in imuconv holds a covariance, symmetric by definition: the preintegrate task stores it
  // symmetrized, so the plugin inverts (C + C^T)/2 in float. C[0:9]'s condition number
  // turns that half-ulp change into up to 4.1e-4 of the information by the metric (smooth-1;
  // computed from the anchor's own C, the difference is the one the task shows), above the
  // 1e-4. So the information is compared with EdgeInertial's formula on the anchor's C made
  // symmetric (inverted in double, symmetrized); the residual, Jacobians and chi2 with the
  // anchor's own numbers. Measured: chi2, weighted by that information, within 8.9e-5 of
  // ORB-SLAM3's (white-0); every other field closer.
  const Eigen::Matrix<double, 9, 9> c9 =
      JsonMatrix(ReadJson(DataPath("reference/anchors/orb-slam3/" + id + ".json"))
                     .at("preintegration")
                     .at("C")
                     .at("matrix"))
          .topLeftCorner<9, 9>();
  const Eigen::Matrix<double, 9, 9> c9_symmetric =
      ((c9 + c9.transpose()) / 2).cast<float>().cast<double>();
  const Eigen::Matrix<double, 9, 9> inverse = c9_symmetric.inverse();
  const Eigen::Matrix<double, 9, 9> information_of_symmetric_c =
      (inverse + inverse.transpose()) / 2;
  for (const auto& [task, key] :
       {std::pair<const char*, const char*>{"at_lin", "at_lin_bias"}, {"at_new", "at_new_bias"}}) {
    const json& t = TaskOutput(out, task);
    ASSERT_EQ(t.at("kind"), "orb_slam3");
    const json& res = t.at("residuals").at(0);
    const json& e = res.at("orb_slam3");
    const json& ref = ej.at(key);
    w.Metric("information (of the symmetrized C)", information_of_symmetric_c,
             JsonMatrix(e.at("information")));
    for (const char* f :
         {"residual", "J_pose1", "J_vel1", "J_gyro_bias1", "J_acc_bias1", "J_pose2", "J_vel2"})
      w.Metric(f, JsonMatrix(ref.at(f)), JsonMatrix(e.at(f)));
    // chi2 is the task's squared distance.
    w.Metric("chi2", Eigen::Matrix<double, 1, 1>(ref.at("chi2").get<double>()),
             Eigen::Matrix<double, 1, 1>(res.at("mahalanobis_squared").get<double>()));
  }
  w.Print();
}

INSTANTIATE_TEST_SUITE_P(Reference, ResidualOrbSlam3, ::testing::ValuesIn(kReferenceCaseIds),
                         CaseTestName);

}  // namespace
