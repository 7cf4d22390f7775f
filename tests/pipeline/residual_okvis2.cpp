// The residual task's kind "okvis2" (plugins/residuals/okvis2.cpp) against OKVIS2's own
// ImuError (tests/data/reference/anchors/okvis2, README.md there): a pipeline over a whole
// reference case preintegrates it with the `okvis2` preintegrator at the anchor's two biases,
// and three residual tasks with the anchor's own states give EvaluateWithMinimalJacobians
// at the linearization bias (`at_lin_bias`), at the new bias to first order (`at_new_bias`,
// the same measurement with state_0's new biases; the anchor's ImuError did not re-integrate,
// redoCounter_after_new_bias 1, as checked) and repropagated (`repropagated`, the measurement
// integrated at the new bias). The path is the pipeline's: the measurement goes through the
// registry (native result, reference charts, expressed in `okvis2`), the states through the
// pipeline's state form (rotation matrices; quaternions only up to sign).
//
// Tolerances, those of tests/reference/okvis2_anchor.cpp and why: the raw Jacobians by the
// note's metric at 1e-8 and relative to entries above 1e-4 of the largest at 1e-9
// (AnchorFieldDiffs::Jacobian); the information on its correlation scale within the anchors'
// 1e-9 or eps cond(P_delta), whichever is larger (any inverse of P_delta is exact only to
// that; okvis2_anchor.cpp measures it); the squared distance r^T information r against the
// anchor's |whitened residual|^2 at 1e-8 relative. The residual's p and v rows: the pipeline
// holds times relative to an origin, through nanoseconds, so its increments differ from the
// anchor's by about 2e-13 relative, and those rows are small differences of terms near
// g T^2 / 2 = 490 m (tests/pipeline/residual_native.cpp measures it for VINS and Basalt):
// beyond 1e-8 by the metric they are held to 1e-12 of the increment they come from
// (|Delta_p|, |Delta_v|), 5x above the measured 2e-13. Measured here: no row beyond 1e-8, the
// raw fields within 5.2e-13 by the metric, the information within 7.9e-10 (smooth-3).
#include <gtest/gtest.h>

#include <limits>
#include <string>

#include <Eigen/Eigenvalues>

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

json Okvis2StateJson(const json& x) { return AnchorStateJson(x, "r"); }

json RunOkvis2Case(const std::string& id, const json& ie) {
  const json c = ReadJson(DataPath("reference/cases/" + id + ".json"));
  const double t0 = c.at("imu").front().at(0), t1 = c.at("imu").back().at(0);
  const json& s0 = ie.at("state_0");
  const json& s0_new = ie.at("state_0_new_bias");
  auto pre = [&](const char* name, const json& s) {
    return PreintegrateTask(name, "okvis2", s, t0, t1);
  };
  auto residual = [&](const char* name, const char* meas, const json& start) {
    return ResidualTask(name, "okvis2", meas, Okvis2StateJson(start),
                        Okvis2StateJson(ie.at("state_1")));
  };
  return RunOverCase(c,
                     {pre("pre_lin", s0), pre("pre_new", s0_new), residual("at_lin", "pre_lin", s0),
                      residual("at_new", "pre_lin", s0_new), residual("repro", "pre_new", s0_new)},
                     id + " (in memory)");
}

class ResidualOkvis2 : public ::testing::TestWithParam<const char*> {};

TEST_P(ResidualOkvis2, KindOkvis2WritesImuErrorAsOkvisDoes) {
  const std::string id = GetParam();
  const json ie = ReadJson(DataPath("reference/anchors/okvis2/" + id + ".json")).at("imu_error");
  ASSERT_EQ(ie.at("redoCounter_after_new_bias").get<int>(), 1);  // first order, not redone
  const json out = RunOkvis2Case(id, ie);
  struct Okvis2Check {
    const char* task;
    const char* meas;
    const json& ref;          // the anchor's evaluation ({raw, whitened})
    const json& information;  // and the information it was weighted with
    const json& P_delta;
  };
  const json& pre_lin = ie.at("preintegration");
  const json& pre_new = ie.at("repropagated").at("preintegration");
  double worst_scaled = 0.0;
  for (const Okvis2Check& k :
       {Okvis2Check{"at_lin", "pre_lin", ie.at("at_lin_bias"), pre_lin.at("information"),
                    pre_lin.at("P_delta").at("matrix")},
        Okvis2Check{"at_new", "pre_lin", ie.at("at_new_bias"), pre_lin.at("information"),
                    pre_lin.at("P_delta").at("matrix")},
        Okvis2Check{"repro", "pre_new", ie.at("repropagated").at("at_new_bias"),
                    pre_new.at("information"), pre_new.at("P_delta").at("matrix")}}) {
    const std::string label = id + " " + k.task;
    const json& task = TaskOutput(out, k.task);
    ASSERT_EQ(task.at("kind"), "okvis2");
    ASSERT_TRUE(task.contains("layout"));
    const json& res = task.at("residuals").at(0);
    const json& raw = res.at("okvis2").at("raw");
    const json& ref = k.ref.at("raw");
    AnchorFieldDiffs w(label);
    for (const char* f :
         {"jacobian_pose_0", "jacobian_speedbias_0", "jacobian_pose_1", "jacobian_speedbias_1",
          "jacobian_pose_0_minimal", "jacobian_pose_1_minimal"})
      w.Jacobian(f, JsonMatrix(ref.at(f)), JsonMatrix(raw.at(f)));
    // The residual: the metric, or 1e-12 of the increment's size (header).
    const json& delta = TaskOutput(out, k.meas).at("measurements").at(0).at("delta");
    const double dp = JsonMatrix(delta.at("dp")).norm(), dv = JsonMatrix(delta.at("dv")).norm();
    const Eigen::VectorXd r_ref = JsonMatrix(ref.at("residual")),
                          r = JsonMatrix(raw.at("residual"));
    ASSERT_EQ(r.size(), 15);
    for (Eigen::Index i = 0; i < 15; ++i) {
      if (EntryDiff(r_ref[i], r[i]) <= kAnchorMetricTol) continue;
      const double scale = i < 3 ? dp : (i >= 6 && i < 9) ? dv : 0.0;
      worst_scaled = std::max(worst_scaled, std::abs(r_ref[i] - r[i]) / scale);
      EXPECT_LE(std::abs(r_ref[i] - r[i]), 1e-12 * scale) << label << ": residual[" << i << "]";
    }
    // The information on its correlation scale (header).
    const Eigen::MatrixXd info_ref = JsonMatrix(k.information);
    const Eigen::MatrixXd info = JsonMatrix(res.at("okvis2").at("information"));
    const ScaledDiff d = CorrelationScaleDiff(info_ref, info);
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(JsonMatrix(k.P_delta));
    const double cond = eig.eigenvalues().maxCoeff() / eig.eigenvalues().minCoeff();
    EXPECT_LE(d.d, std::max(kAnchorScaledTol, std::numeric_limits<double>::epsilon() * cond))
        << label << ": information at (" << d.row << "," << d.col << ")";
    // The task's squared distance is OKVIS's: |whitened residual|^2 = r^T information r.
    const double chi2_ref = JsonMatrix(k.ref.at("whitened").at("residual")).squaredNorm();
    EXPECT_NEAR(res.at("mahalanobis_squared").get<double>(), chi2_ref,
                kAnchorMetricTol * std::max(1.0, chi2_ref))
        << label;
    w.Print();
    std::printf("  %-34s information %.2g on the correlation scale\n", "", d.d);
  }
  std::printf("  %-13s residual rows beyond the metric: %.2g of the increment\n", id.c_str(),
              worst_scaled);
}

INSTANTIATE_TEST_SUITE_P(Reference, ResidualOkvis2, ::testing::ValuesIn(kReferenceCaseIds),
                         CaseTestName);

}  // namespace
