// imuconv check, issue 23: the ranking of explanations (a relative tie tolerance), block-level
// findings and equivalent explanations, on GTSAM's reference numbers
// (tests/data/reference/gtsam, zero-order-hold ManifoldPreintegration) with one defect of
// each kind planted here.
//
// What is asserted is what the planted defect is, not what the program printed: the block
// and kind planted, the factor planted (a scale planted as U = f K exactly is fitted back to
// f up to round-off: 1e-9 relative, the tie tolerance of explain.cpp, far above the ~1e-15 of
// a least-squares quotient of nine products), and nothing else found.
#include <gtest/gtest.h>

#include <set>
#include <string>
#include <vector>

#include "../pipeline/pipeline_test_util.h"
#include "gtsam_measurement.h"
#include "imuconv_test.h"
#include "json_rows.h"
#include "json_schema_check.h"

namespace {
using namespace imuconv;
using namespace imuconv::test;
using nlohmann::json;

// GTSAM's block indices: J_bias rows theta 0, p 3, v 6, columns ba 0, bg 3; cov15 theta 0,
// p 3, v 6, ba 9, bg 12.
constexpr int kTheta = 0, kP = 3, kV = 6, kBa = 9, kBg = 12;
constexpr int kColBa = 0, kColBg = 3;

const char* const kBlocksCase = "smooth-0";

/// The largest |K_ij| / sqrt(K_ii K_jj) over the 3x3 block of `K` at (r, c): what check's
/// difference (the correlation scale) makes of that block's entries.
double BlockCorrelation(const Eigen::MatrixXd& K, int r, int c) {
  double m = 0.0;
  for (int i = r; i < r + 3; ++i)
    for (int j = c; j < c + 3; ++j)
      m = std::max(m, std::abs(K(i, j)) / std::sqrt(K(i, i) * K(j, j)));
  return m;
}

constexpr double kTol = 1e-2;  // check's tolerance on each max d (apps/check/verdict.cpp)

class CheckBlocks : public ::testing::Test {
 protected:
  static TempDir& Tmp() {
    static TempDir tmp;
    return tmp;
  }
  /// imuconv check --json on one measurement: measurement 0 of the output.
  static json Run(const json& m, const std::string& name, int expect_exit = 1) {
    const std::string file = Tmp().write(name + ".json", json{{"measurements", {m}}}.dump());
    const CommandResult r = RunImuconv(
        "check " + ShellQuote(file) + " --case " +
            ShellQuote(DataPath("reference/cases/" + std::string(kBlocksCase) + ".json")) +
            " --json",
        Tmp());
    EXPECT_EQ(r.exit_code, expect_exit) << name << "\n" << r.err << r.out;
    if (r.exit_code != 0 && r.exit_code != 1) return json::object();
    const json out = json::parse(r.out);
    // Each --json output against the schema in the test that made it: ctest runs every test in
    // its own process.
    ExpectFollowsSchema(Tmp(), "schemas/check_output.schema.json", json::array({out}), name);
    return out["measurements"][0];
  }
  /// Run on the measurement `m` with its J_bias replaced by `J`.
  static json RunWithJacobian(json m, const Eigen::MatrixXd& J, const std::string& name) {
    m["J_bias"]["matrix"] = JsonRows(J);
    return Run(m, name);
  }
  static std::string Findings(const json& m) {
    std::string s;
    for (const auto& f : m["findings"]) s += f.get<std::string>() + "\n";
    return s;
  }
  /// The block finding `f` names a defect of kind `kind` in the block (rows, cols).
  static void ExpectBlockFinding(const json& f, const std::string& kind,
                                 const std::vector<std::string>& rows,
                                 const std::vector<std::string>& cols) {
    EXPECT_EQ(f["kind"], kind);
    EXPECT_EQ(f["rows"], json(rows));
    EXPECT_EQ(f["cols"], json(cols));
  }
  static double SamplePeriod() {
    const json c = CaseJson(kBlocksCase);
    return c["imu"][1][0].get<double>() - c["imu"][0][0].get<double>();
  }
};

// The ranking bug of issue 23: one 3x3 block of J_bias negated (rows theta, columns bg),
// everything declared correctly. Under the declaration 9 of the 54 entries are off by 2 (mean
// d at most 1/3); with every block negated ("sign -") the other 45 are (mean 5/3 of the
// nonzero ones, 1.33 here). Both have max d 2 to within 1e-14, which a tie tolerance that is
// absolute read as a difference and named "sign -".
TEST_F(CheckBlocks, OneNegatedBlockKeepsTheDeclaredChartAndNamesTheBlock) {
  Eigen::MatrixXd J, cov;
  json m = GtsamMeasurement(kBlocksCase, &J, &cov);
  J.block<3, 3>(kTheta, kColBg) *= -1.0;
  const json r = RunWithJacobian(m, J, "negated-block");
  ASSERT_TRUE(r.contains("best")) << r.dump(1);
  EXPECT_EQ(r["best"]["J_bias_sign"], 1) << Findings(r);
  EXPECT_EQ(r["best"]["jacobian_convention"], r["declared"]["jacobian_convention"]);
  EXPECT_EQ(r["best"]["J_bias_columns"], json({"ba", "bg"}));
  EXPECT_LE(r["best"]["J_bias"]["mean_d"].get<double>(), 1.0 / 3.0 + 1e-9);
  ASSERT_EQ(r["block_findings"].size(), 1u) << r["block_findings"].dump(1);
  const json& f = r["block_findings"][0];
  EXPECT_EQ(f["matrix"], "J_bias");
  ExpectBlockFinding(f, "sign", {"theta"}, {"bg"});
  EXPECT_EQ(f["factor"], -1.0);
  EXPECT_TRUE(r["unexplained_blocks"].empty());
  EXPECT_TRUE(Has(Findings(r), "J_bias block (rows theta, cols bg) has the opposite sign"))
      << Findings(r);
}

// J_bias's (p, ba) block per step (x 1/dt, dt the sample period).
TEST_F(CheckBlocks, JacobianBlockScaledByOneOverDtIsNamed) {
  Eigen::MatrixXd J, cov;
  json m = GtsamMeasurement(kBlocksCase, &J, &cov);
  const double dt = SamplePeriod();
  J.block<3, 3>(kP, kColBa) /= dt;
  const json r = RunWithJacobian(m, J, "scaled-jacobian-block");
  ASSERT_EQ(r["block_findings"].size(), 1u) << r["block_findings"].dump(1) << Findings(r);
  const json& f = r["block_findings"][0];
  EXPECT_EQ(f["matrix"], "J_bias");
  ExpectBlockFinding(f, "scale", {"p"}, {"ba"});
  EXPECT_NEAR(f["factor"].get<double>() * dt, 1.0, 1e-9);
  EXPECT_TRUE(Has(Findings(r), "J_bias block (rows p, cols ba) is scaled by 1/dt")) << Findings(r);
}

TEST_F(CheckBlocks, SwappedJacobianBlocksAreNamed) {
  Eigen::MatrixXd J, cov;
  json m = GtsamMeasurement(kBlocksCase, &J, &cov);
  const Eigen::Matrix3d a = J.block<3, 3>(kP, kColBa), b = J.block<3, 3>(kP, kColBg);
  J.block<3, 3>(kP, kColBa) = b;
  J.block<3, 3>(kP, kColBg) = a;
  const json r = RunWithJacobian(m, J, "swapped-jacobian-blocks");
  EXPECT_EQ(r["best"]["J_bias_columns"], json({"ba", "bg"})) << Findings(r);
  ASSERT_EQ(r["block_findings"].size(), 1u) << r["block_findings"].dump(1) << Findings(r);
  const json& f = r["block_findings"][0];
  ExpectBlockFinding(f, "swap", {"p", "p"}, {"ba", "bg"});
  EXPECT_EQ(f["factor"], 1.0);
}

TEST_F(CheckBlocks, TransposedJacobianBlockIsNamed) {
  Eigen::MatrixXd J, cov;
  json m = GtsamMeasurement(kBlocksCase, &J, &cov);
  const Eigen::Matrix3d t = J.block<3, 3>(kV, kColBg).transpose();
  // The block must not be symmetric, or its transpose would be the same numbers.
  ASSERT_GT((t - t.transpose()).cwiseAbs().maxCoeff(), 0.1 * t.cwiseAbs().maxCoeff());
  J.block<3, 3>(kV, kColBg) = t;
  const json r = RunWithJacobian(m, J, "transposed-jacobian-block");
  ASSERT_EQ(r["block_findings"].size(), 1u) << r["block_findings"].dump(1) << Findings(r);
  const json& f = r["block_findings"][0];
  ExpectBlockFinding(f, "transpose", {"v"}, {"bg"});
}

// The gyro bias's cross terms never formed (ORB-SLAM3 forms none): each block of them whose
// zeroing the difference can see (a correlation above the tolerance in the reference) is found
// missing, and nothing else. (With every state-bias cross term zeroed, the nearest explanation
// is rightly Basalt's scheme, whose covariance has none, within 1 % but for the v block; hence
// only bg's here, which keeps the matrix positive semi-definite: bg decoupled from the rest.)
TEST_F(CheckBlocks, MissingCrossTermsAreNamed) {
  Eigen::MatrixXd J, cov;
  json m = GtsamMeasurement(kBlocksCase, &J, &cov);
  std::set<std::pair<std::string, std::string>> expect;
  const std::pair<const char*, int> state[] = {{"theta", kTheta}, {"p", kP}, {"v", kV}};
  for (const auto& [s, r] : state)
    if (BlockCorrelation(cov, r, kBg) > kTol) expect.insert({s, "bg"});
  ASSERT_GE(expect.size(), 2u);  // the case has cross terms to miss
  // (ba, bg) is zero in the reference too (independent random walks).
  cov.block<12, 3>(0, kBg).setZero();
  cov.block<3, 12>(kBg, 0).setZero();
  m["cov"]["matrix"] = JsonRows(cov);
  const json r = Run(m, "missing-cross-terms");
  EXPECT_EQ(r["best"]["scheme"], "euler") << r["best"].dump();
  EXPECT_EQ(r["best"]["convention"], "gtsam_manifold");
  EXPECT_EQ(r["best"]["blocks"], json({"theta", "p", "v", "ba", "bg"}));
  EXPECT_TRUE(r["unexplained_blocks"].empty()) << r["unexplained_blocks"].dump(1);
  std::set<std::pair<std::string, std::string>> found;
  for (const json& f : r["block_findings"]) {
    EXPECT_EQ(f["matrix"], "cov");
    EXPECT_EQ(f["kind"], "missing") << f.dump();
    EXPECT_EQ(f["factor"], 0.0);
    found.insert({f["rows"][0].get<std::string>(), f["cols"][0].get<std::string>()});
  }
  EXPECT_EQ(found, expect) << r["block_findings"].dump(1);
  EXPECT_TRUE(Has(Findings(r), "is zero where the reference is not")) << Findings(r);
}

// The bg cross terms negated: GTSAM's cov15 with d(bias) read as b_hat - b for bg only. Each
// such block the difference can see (negation changes an entry by twice its correlation) is
// found with the opposite sign.
TEST_F(CheckBlocks, NegatedCovarianceBlocksAreNamed) {
  Eigen::MatrixXd J, cov;
  json m = GtsamMeasurement(kBlocksCase, &J, &cov);
  std::set<std::string> expect;
  for (const auto& [s, r] :
       {std::pair<const char*, int>{"theta", kTheta}, {"p", kP}, {"v", kV}, {"ba", kBa}})
    if (2.0 * BlockCorrelation(cov, r, kBg) > kTol) expect.insert(s);
  ASSERT_GE(expect.size(), 2u);
  Eigen::VectorXd s = Eigen::VectorXd::Ones(15);
  s.segment<3>(kBg).setConstant(-1.0);
  cov = s.asDiagonal() * cov * s.asDiagonal();
  m["cov"]["matrix"] = JsonRows(cov);
  const json r = Run(m, "negated-cov-blocks");
  EXPECT_EQ(r["best"]["blocks"], json({"theta", "p", "v", "ba", "bg"}));
  EXPECT_TRUE(r["unexplained_blocks"].empty()) << r["unexplained_blocks"].dump(1);
  std::set<std::string> rows;
  for (const json& f : r["block_findings"]) {
    EXPECT_EQ(f["kind"], "sign") << f.dump();
    EXPECT_EQ(f["cols"], json({"bg"})) << f.dump();
    rows.insert(f["rows"][0]);
  }
  EXPECT_EQ(rows, expect) << r["block_findings"].dump(1);
}

// A variance block doubled, and one multiplied by 1/dt (a per-step variance where a
// density is meant); each adds a positive semi-definite term, so the covariance stays valid.
TEST_F(CheckBlocks, ScaledCovarianceBlocksAreNamedWithTheirFactors) {
  Eigen::MatrixXd J, cov;
  json m = GtsamMeasurement(kBlocksCase, &J, &cov);
  const double dt = SamplePeriod();
  cov.block<3, 3>(kP, kP) *= 2.0;
  cov.block<3, 3>(kBa, kBa) /= dt;
  m["cov"]["matrix"] = JsonRows(cov);
  const json r = Run(m, "scaled-cov-blocks");
  EXPECT_EQ(r["best"]["blocks"], json({"theta", "p", "v", "ba", "bg"})) << Findings(r);
  EXPECT_TRUE(r["unexplained_blocks"].empty()) << r["unexplained_blocks"].dump(1);
  ASSERT_EQ(r["block_findings"].size(), 2u) << r["block_findings"].dump(1);
  const json& p = r["block_findings"][0];
  ExpectBlockFinding(p, "scale", {"p"}, {"p"});
  EXPECT_NEAR(p["factor"].get<double>(), 2.0, 2.0 * 1e-9);
  const json& ba = r["block_findings"][1];
  ExpectBlockFinding(ba, "scale", {"ba"}, {"ba"});
  EXPECT_NEAR(ba["factor"].get<double>() * dt, 1.0, 1e-9);
  EXPECT_TRUE(Has(Findings(r), "cov block (rows p, cols p) is scaled by 2 ")) << Findings(r);
  EXPECT_TRUE(Has(Findings(r), "cov block (rows ba, cols ba) is scaled by 1/dt")) << Findings(r);
}

// J_bias negated under GTSAM's declared chart: `gtsam_manifold_jacobian` (whose theta, p, v
// blocks are the reference's) with sign - and `forster` (all blocks negated) with sign + are the
// same numbers. The declared chart is named, the other listed as equivalent, on every run.
TEST_F(CheckBlocks, EquivalentExplanationsAreListedAndThePickIsStable) {
  Eigen::MatrixXd J, cov;
  json m = GtsamMeasurement(kBlocksCase, &J, &cov);
  m["J_bias"]["matrix"] = JsonRows(-J);
  const json first = Run(m, "equivalent-1");
  const json again = Run(m, "equivalent-2");
  ASSERT_TRUE(first.contains("best"));
  EXPECT_EQ(first["best"], again["best"]);
  EXPECT_EQ(first["equivalent"], again["equivalent"]);
  EXPECT_EQ(first["best"]["jacobian_convention"], "gtsam_manifold_jacobian");
  EXPECT_EQ(first["best"]["J_bias_sign"], -1);
  const json forster = {
      {"jacobian_convention", "forster"}, {"J_bias_columns", {"ba", "bg"}}, {"J_bias_sign", 1}};
  bool listed = false;
  for (const json& e : first["equivalent"]["J_bias"]) listed = listed || e == forster;
  EXPECT_TRUE(listed) << first["equivalent"].dump(1);
  EXPECT_TRUE(Has(Findings(first), "these are the same numbers")) << Findings(first);
  EXPECT_TRUE(Has(Findings(first), "J_bias in forster [ba, bg] +")) << Findings(first);
}

TEST_F(CheckBlocks, ConsistentWithNothingDeclaredDoesNotSayDeclared) {
  Eigen::MatrixXd J, cov;
  json m = GtsamMeasurement(kBlocksCase, &J, &cov);
  m["J_bias"] = {{"convention", "unknown"}, {"matrix", m["J_bias"]["matrix"]}};
  m["cov"] = {{"convention", "unknown"}, {"matrix", m["cov"]["matrix"]}};
  const json r = Run(m, "nothing-declared", 0);
  EXPECT_FALSE(Has(Findings(r), "under the declared")) << Findings(r);
  EXPECT_TRUE(Has(Findings(r), "no chart was declared")) << Findings(r);
  const json d = Run(GtsamMeasurement(kBlocksCase, &J, &cov), "declared", 0);
  EXPECT_TRUE(Has(Findings(d), "under the declared covariance convention gtsam_manifold"))
      << Findings(d);
}

// The precision of the numbers and dt (the measurements reader's rule, measurement.h): a
// covariance asymmetric at 1e-6 on the correlation scale is refused in double precision
// (tolerance 1e-9) and judged in float32 (1e-4); a dt 0.5 s off the interval is said and
// makes the verdict inconsistent (far beyond the 2000 x 2^-53 x 10 s a double sum can lose);
// a "precision" that is neither is refused at its pointer.
TEST_F(CheckBlocks, PrecisionAndDtAreJudgedNotRefused) {
  Eigen::MatrixXd J, cov;
  json m = GtsamMeasurement(kBlocksCase, &J, &cov);
  Eigen::MatrixXd asym = cov;
  asym(kP, kTheta) += 1e-6 * std::sqrt(cov(kP, kP) * cov(kTheta, kTheta));
  json a = m;
  a["cov"]["matrix"] = JsonRows(asym);
  {
    const std::string file = Tmp().write("asym64.json", json{{"measurements", {a}}}.dump());
    const CommandResult r = RunImuconv(
        "check " + ShellQuote(file) + " --case " +
            ShellQuote(DataPath(std::string("reference/cases/") + kBlocksCase + ".json")),
        Tmp());
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_TRUE(Has(r.err, "/measurements/0/cov/matrix")) << r.err;
  }
  a["precision"] = "float32";
  const json f32 = Run(a, "asym32", 0);
  EXPECT_EQ(f32["precision"], json({{"numbers", "float32"}, {"inferred", false}}));
  EXPECT_TRUE(Has(Findings(f32), "single precision (declared")) << Findings(f32);

  json late = m;
  late["dt"] = m["dt"].get<double>() + 0.5;
  const json d = Run(late, "dt-off", 1);
  EXPECT_NEAR(d["dt_difference"].get<double>(), 0.5, 1e-9);
  EXPECT_EQ(d["verdict"], "inconsistent");
  EXPECT_TRUE(Has(Findings(d), "dt is not the interval's duration")) << Findings(d);

  json bad = m;
  bad["precision"] = "float16";
  const std::string file = Tmp().write("float16.json", json{{"measurements", {bad}}}.dump());
  const CommandResult r =
      RunImuconv("check " + ShellQuote(file) + " --case " +
                     ShellQuote(DataPath(std::string("reference/cases/") + kBlocksCase + ".json")),
                 Tmp());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Has(r.err, "/measurements/0/precision")) << r.err;
}

}  // namespace
