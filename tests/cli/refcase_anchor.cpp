// `imuconv refcase CASE.json --anchor NAME -o OUT.json` against the anchor files themselves
// (tests/data/reference/anchors/NAME/, README.md there): on all ten reference cases, every
// computed field of the anchor file (all but `inputs`, `upstream`, `build`) must be in the
// command's output under the same name and layout, and agree.
//
// Tolerances. Every field: 1e-8 by the metric of J. Huai, "IMU Propagation as Preintegration"
// (relative above 1e-4, absolute below; anchors.h explains the bound: round-off of the same
// formulas accumulated over 2000 steps). VINS-Fusion's whitened fields (factor/sqrt_info,
// factor/whitened/*): 1e-5, because sqrt_info is the Cholesky factor of the inverse of a
// covariance of condition number about 1e9, which turns the covariance's round-off into up to
// about 1e-7 (issue 12). Integer fields (nanosecond times) and strings: equal. For `openvins`
// a method is compared when its propagator is registered (`openvins_discrete` always is); the
// output's methods_written must name exactly those. For `okvis2` the fields that depend on an
// eigen-solver's choices are judged by what does not depend on them (OkvisSignFreeFields).
// The worst difference of each field over the ten cases is printed.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cstdio>
#include <limits>
#include <map>
#include <string>

#include "../pipeline/pipeline_test_util.h"
#include "imuconv_test.h"
#include "scale_aware.h"

namespace {
using namespace imuconv::test;
using nlohmann::json;

constexpr double kFieldTol = 1e-8;
constexpr double kWhitenedTol = 1e-5;

/// The worst difference per field (array indices dropped from the pointer).
using FieldWorst = std::map<std::string, double>;

bool Whitened(const std::string& field) {
  return field.rfind("/factor/sqrt_info", 0) == 0 || field.rfind("/factor/whitened", 0) == 0;
}

/// Compares the anchor's value `a` with the output's `o` at JSON pointer `ptr` (`field` the
/// pointer without indices), recording numeric differences and failing on anything else.
void Compare(const json& a, const json& o, const std::string& ptr, const std::string& field,
             const std::string& label, FieldWorst& worst) {
  if (a.is_object()) {
    ASSERT_TRUE(o.is_object()) << label << ": " << ptr << " is not an object";
    for (auto it = a.begin(); it != a.end(); ++it) {
      if (ptr.empty() && (it.key() == "inputs" || it.key() == "upstream" || it.key() == "build"))
        continue;
      ASSERT_TRUE(o.contains(it.key())) << label << ": the output lacks " << ptr << "/" << it.key();
      Compare(it.value(), o.at(it.key()), ptr + "/" + it.key(), field + "/" + it.key(), label,
              worst);
    }
  } else if (a.is_array()) {
    ASSERT_TRUE(o.is_array() && o.size() == a.size())
        << label << ": " << ptr << " has another size";
    for (std::size_t i = 0; i < a.size(); ++i)
      Compare(a[i], o[i], ptr + "/" + std::to_string(i), field, label, worst);
  } else if (a.is_number_integer()) {
    EXPECT_EQ(a, o) << label << ": " << ptr;
  } else if (a.is_number()) {
    ASSERT_TRUE(o.is_number()) << label << ": " << ptr << " is not a number";
    const double d = EntryDiff(a.get<double>(), o.get<double>());
    double& w = worst[field];
    w = std::max(w, d);
    EXPECT_LE(d, Whitened(field) ? kWhitenedTol : kFieldTol) << label << ": " << ptr;
  } else {
    EXPECT_EQ(a, o) << label << ": " << ptr;
  }
}

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
void OkvisSignFreeFields(json& anchor, json& out, const std::string& label, FieldWorst& worst) {
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

void RunAnchor(const std::string& name) {
  TempDir tmp;
  FieldWorst worst;
  for (const char* id : kReferenceCaseIds) {
    const std::string case_path = DataPath(std::string("reference/cases/") + id + ".json");
    const std::string out_path = tmp.file(name + "-" + id + ".json");
    const CommandResult r = RunImuconv(
        "refcase " + ShellQuote(case_path) + " --anchor " + name + " -o " + ShellQuote(out_path),
        tmp);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    json anchor = ReadJson(DataPath("reference/anchors/" + name + "/" + id + ".json"));
    json out = ReadJson(out_path);
    EXPECT_EQ(out.at("anchor"), name);
    if (name == "okvis2") OkvisSignFreeFields(anchor, out, name + " " + id, worst);
    if (name == "openvins") {
      json expected = json::array();
      for (const auto& [key, plugin] :
           {std::pair<const char*, const char*>{"discrete", "openvins_discrete"},
            {"rk4", "openvins_rk4"},
            {"analytical", "openvins_analytical"}}) {
        if (Plugins().has(imuconv::PluginKind::Propagator, plugin))
          expected.push_back(plugin);
        else
          anchor.erase(key);  // not computable here: reported by the output, not compared
      }
      ASSERT_EQ(out.at("methods_written"), expected) << id;
      ASSERT_TRUE(anchor.contains("discrete"));
    }
    Compare(anchor, out, "", "", name + " " + id, worst);
  }
  std::printf("  %s: worst over the ten cases, by the note's metric\n", name.c_str());
  for (const auto& [field, d] : worst) std::printf("    %-58s %.2g\n", field.c_str(), d);
}

TEST(RefcaseAnchor, VinsFusionFieldsAreVinsFusionOwn) { RunAnchor("vins-fusion"); }
TEST(RefcaseAnchor, BasaltFieldsAreBasaltOwn) { RunAnchor("basalt"); }
TEST(RefcaseAnchor, OpenVinsFieldsAreOpenVinsOwn) { RunAnchor("openvins"); }
TEST(RefcaseAnchor, OrbSlam3FieldsAreOrbSlam3Own) { RunAnchor("orb-slam3"); }
TEST(RefcaseAnchor, Okvis2FieldsAreOkvis2Own) { RunAnchor("okvis2"); }
TEST(RefcaseAnchor, FastLio2FieldsAreFastLioOwn) { RunAnchor("fast-lio2"); }

TEST(RefcaseAnchor, UnknownNameIsRefusedAndNothingWritten) {
  TempDir tmp;
  const CommandResult r =
      RunImuconv("refcase " + ShellQuote(DataPath("reference/cases/smooth-0.json")) +
                     " --anchor orbslam3 -o " + ShellQuote(tmp.file("out.json")),
                 tmp);
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("orbslam3"), std::string::npos) << r.err;
  EXPECT_FALSE(std::ifstream(tmp.file("out.json")).good());
}

}  // namespace
