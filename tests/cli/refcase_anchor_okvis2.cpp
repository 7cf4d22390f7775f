// OKVIS2's rule for `imuconv refcase --anchor okvis2` against its anchor files
// (refcase_anchor.cpp runs it before the generic comparison, refcase_anchor.h): the fields an
// eigen-solver chooses are judged by what does not depend on the choice.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "imuconv_test.h"
#include "refcase_anchor.h"
#include "scale_aware.h"

namespace {
using namespace imuconv::test;
using namespace imuconv::test::refcase_anchor;
using nlohmann::json;

/// OKVIS2's squareRootInformation is D^1/2 V^T of an eigen-decomposition of P_delta (the
/// anchors' README): its rows' signs, and where eigenvalues coincide (the three gyro-bias
/// directions nearly do) their basis, are the solver's choice, and `whitened` is that S times
/// `raw`. Neither is compared entry by entry; what does not depend on the choice is:
///  - information: the anchor's against the output's on the correlation scale, within
///    max(1e-9, eps cond(P_delta)): any inverse of P_delta (condition number 2.4e8..2.4e11
///    here) is exact only to eps times that, so cancelling entries differ by up to 1.5e-5 by
///    the note's metric whoever inverts (tests/reference/okvis2_anchor.cpp measured 7.9e-10
///    on the correlation scale at most);
///  - S^T S = information: the output's S against the anchor's information, same bound;
///  - whitened residual: its squared norm (OKVIS's cost, raw^T information raw), relative
///    1e-8 (the information's bound does not reach it: the residual's weight on a
///    cancelling entry is small);
///  - whitened Jacobians W = S J: S_o^T W_o = information J, the output's, against the
///    anchor's information times the anchor's raw J, on the scale of each column's largest
///    entry, within the information's bound.
/// The raw fields, P_delta and the rest go through the generic rule. The fields judged here
/// are removed from both documents before it.
void Okvis2SignFreeFields(json& anchor, json& out, const std::string& label, FieldWorst& worst) {
  const double eps = std::numeric_limits<double>::epsilon();
  struct Pair {
    const char* pre;
    std::vector<const char*> evaluations;
  };
  const Pair pairs[] = {
      {"/imu_error/preintegration", {"/imu_error/at_lin_bias", "/imu_error/at_new_bias"}},
      {"/imu_error/repropagated/preintegration", {"/imu_error/repropagated/at_new_bias"}}};
  for (const Pair& p : pairs) {
    const json::json_pointer pre(p.pre);
    ASSERT_TRUE(anchor.contains(pre) && out.contains(pre)) << label << ": " << p.pre;
    const Eigen::MatrixXd P = JsonMatrix(anchor.at(pre).at("P_delta").at("matrix"));
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(P);
    const double bound =
        std::max(1e-9, eps * eig.eigenvalues().maxCoeff() / eig.eigenvalues().minCoeff());
    const Eigen::MatrixXd info_a = JsonMatrix(anchor.at(pre).at("information"));
    const Eigen::MatrixXd info_o = JsonMatrix(out.at(pre).at("information"));
    const Eigen::MatrixXd S_o = JsonMatrix(out.at(pre).at("squareRootInformation"));
    const auto record = [&](const std::string& field, const ScaledDiff& s, double tol) {
      double& w = worst[field + " (sign-free)"];
      w = std::max(w, s.d);
      EXPECT_LE(s.d, tol) << label << ": " << field << " at (" << s.row << "," << s.col << ")";
    };
    record(std::string(p.pre) + "/information", CorrelationScaleDiff(info_a, info_o), bound);
    record(std::string(p.pre) + "/squareRootInformation",
           CorrelationScaleDiff(info_a, Eigen::MatrixXd(S_o.transpose() * S_o)), bound);
    for (const char* e : p.evaluations) {
      const json::json_pointer ev(e);
      const json& wa = anchor.at(ev).at("whitened");
      const json& wo = out.at(ev).at("whitened");
      const json& raw_a = anchor.at(ev).at("raw");
      const double chi2_a = JsonMatrix(wa.at("residual")).squaredNorm();
      const double chi2_o = JsonMatrix(wo.at("residual")).squaredNorm();
      const double d_chi2 = std::abs(chi2_o - chi2_a) / std::max(1.0, chi2_a);
      double& w = worst[std::string(e) + "/whitened/residual (squared norm)"];
      w = std::max(w, d_chi2);
      EXPECT_LE(d_chi2, kFieldTol)
          << label << ": " << e << "/whitened/residual, chi2 " << chi2_o << " against " << chi2_a;
      for (auto it = wo.begin(); it != wo.end(); ++it) {
        if (it.key() == "residual") continue;
        const Eigen::MatrixXd expected = info_a * JsonMatrix(raw_a.at(it.key()));
        const Eigen::MatrixXd got = S_o.transpose() * JsonMatrix(it.value());
        double d = 0.0;
        for (Eigen::Index c = 0; c < expected.cols(); ++c) {
          const double scale = expected.col(c).cwiseAbs().maxCoeff();
          if (scale > 0.0)
            d = std::max(d, (got.col(c) - expected.col(c)).cwiseAbs().maxCoeff() / scale);
          else
            d = std::max(d, got.col(c).cwiseAbs().maxCoeff());
        }
        double& wj = worst[std::string(e) + "/whitened/" + it.key() + " (S^T W)"];
        wj = std::max(wj, d);
        EXPECT_LE(d, bound) << label << ": " << e << "/whitened/" << it.key();
      }
      for (json* doc : {&anchor, &out}) doc->at(ev).erase("whitened");
    }
    for (json* doc : {&anchor, &out}) {
      doc->at(pre).erase("information");
      doc->at(pre).erase("squareRootInformation");
    }
  }
}

IMUCONV_REFCASE_ANCHOR_RULE(okvis2, "okvis2", &Okvis2SignFreeFields);

}  // namespace
