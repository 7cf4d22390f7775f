// imuconv convert: the one-shot conversion against the registry it wraps, round trips through
// its own output, and its refusals (each names the file and pointer, or the option).
#include <gtest/gtest.h>

#include <string>

#include "../pipeline/pipeline_test_util.h"
#include "imuconv/pipeline/json_io.h"
#include "imuconv_test.h"

namespace {
using namespace imuconv::test;
using imuconv::Mat15;
using nlohmann::json;

json MatrixJson(const Mat15& m) {
  json rows = json::array();
  for (int i = 0; i < 15; ++i) {
    json r = json::array();
    for (int k = 0; k < 15; ++k) r.push_back(m(i, k));
    rows.push_back(r);
  }
  return rows;
}

/// A covariance with every block coupled, well conditioned: A A^T + I/10.
Mat15 SomeCovariance() {
  Mat15 A;
  std::normal_distribution<double> n(0.0, 1.0);
  for (int i = 0; i < 15; ++i)
    for (int k = 0; k < 15; ++k) A(i, k) = n(Rng());
  Mat15 S = A * A.transpose() + 0.1 * Mat15::Identity();
  return 0.5 * (S + S.transpose());
}

double MaxAbs(const Eigen::MatrixXd& m) { return m.cwiseAbs().maxCoeff(); }

// The command and the test run the same library code on the same numbers: the state file
// is read by the same reader, the matrix file holds doubles printed to round trip, and the
// output prints the result to round trip. So the two agree to the last bit; the bound
// allows one ulp of the largest entry for a differently ordered sum, nothing more.
constexpr double kSameComputationUlps = 1.0 * std::numeric_limits<double>::epsilon();

TEST(CliConvert, StateCovarianceMatchesTheRegistryAndRoundTrips) {
  TempDir tmp;
  const std::string state = SourcePath("examples/hover.state.json");
  const imuconv::ImuState x = imuconv::pipeline::ReadStateFile(state);
  const Mat15 S = SomeCovariance();
  const std::string m = tmp.write("cov.json", MatrixJson(S).dump());
  CommandResult r =
      RunImuconv("convert --what covariance --from openvins_jpl --to gtsam_navstate --state " +
                     ShellQuote(state) + " --matrix " + ShellQuote(m) + " --json",
                 tmp);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json j = json::parse(r.out);
  EXPECT_EQ(j["result"]["convention"], "gtsam_navstate");
  EXPECT_EQ(j["result"]["blocks"], json({"theta", "p", "v", "ba", "bg"}));
  EXPECT_EQ(j["input"]["convention"], "openvins_jpl");
  const Mat15 expect = Plugins().convert_covariance("openvins_jpl", "gtsam_navstate", x, S);
  const Mat15 got = JsonMatrix(j["result"]["matrix"]);
  EXPECT_LE(MaxAbs(got - expect), kSameComputationUlps * MaxAbs(expect));
  EXPECT_EQ(JsonMatrix(j["input"]["matrix"]), Eigen::MatrixXd(S));

  // Back, from the command's own output: its "result" object declares its convention and
  // blocks, so --from may be left out. J_{A<-B} J_{B<-A} = I up to round-off of the two
  // 15x15 products, so S comes back to a few ulps of its largest entry (3e-16 relative
  // measured on one draw); 1e-14 leaves room for other draws and catches any wrong block.
  const std::string back_in = tmp.write("navstate_cov.json", j["result"].dump());
  r = RunImuconv("convert --what covariance --to openvins_jpl --state " + ShellQuote(state) +
                     " --matrix " + ShellQuote(back_in) + " --json",
                 tmp);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Mat15 back = JsonMatrix(json::parse(r.out)["result"]["matrix"]);
  EXPECT_LE(MaxAbs(back - S), 1e-14 * MaxAbs(S));
}

TEST(CliConvert, TransitionAndIncrementCovarianceMatchTheRegistry) {
  TempDir tmp;
  const imuconv::ImuState xs = TestStates()[2];
  imuconv::ImuState xe = xs;
  xe.R = xs.R * imuconv::so3::Exp(imuconv::Vec3(0.1, -0.2, 0.3));
  xe.p += imuconv::Vec3(0.5, 0.1, -0.2);
  xe.v += imuconv::Vec3(-0.3, 0.2, 0.1);
  const std::string s = tmp.write("s.json", imuconv::pipeline::StateToJson(xs).dump());
  const std::string e = tmp.write("e.json", imuconv::pipeline::StateToJson(xe).dump());
  Mat15 Phi = SomeCovariance();  // any matrix: a transition need not be symmetric
  Phi(0, 14) += 3.0;
  const std::string m = tmp.write("phi.json", MatrixJson(Phi).dump());
  CommandResult r =
      RunImuconv("convert --what transition --from left --to forster --state " + ShellQuote(s) +
                     " --state-end " + ShellQuote(e) + " --matrix " + ShellQuote(m) + " --json",
                 tmp);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // The state files go through the reader (the quaternion is normalised): compare with the
  // states as read back, the same inputs the command used.
  const auto xs_read = imuconv::pipeline::ReadStateFile(s),
             xe_read = imuconv::pipeline::ReadStateFile(e);
  const Mat15 expect = Plugins().convert_transition("left", "forster", xs_read, xe_read, Phi);
  EXPECT_LE(MaxAbs(JsonMatrix(json::parse(r.out)["result"]["matrix"]) - expect),
            kSameComputationUlps * MaxAbs(expect));

  // An increment covariance, GTSAM's manifold chart to Forster's, at an increment file.
  const std::string d = tmp.write(
      "d.json",
      R"({"q_wxyz": [0.9, 0.1, -0.3, 0.2], "dp": [0.4, -0.2, 1.1], "dv": [0.9, 0.3, -0.5], "dbg": [0, 0, 0], "dba": [0, 0, 0]})");
  const Mat15 S = SomeCovariance();
  const std::string c = tmp.write("c.json", MatrixJson(S).dump());
  // (Not a unit quaternion: the reader refuses it, naming the file.)
  r = RunImuconv(
      "convert --what increment_covariance --from gtsam_manifold --to forster --increment " +
          ShellQuote(d) + " --matrix " + ShellQuote(c),
      tmp);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Has(r.err, d + ": /q_wxyz: expected a unit quaternion")) << r.err;

  const Eigen::Quaterniond q = Eigen::Quaterniond(0.9, 0.1, -0.3, 0.2).normalized();
  const std::string d2 = tmp.write("d2.json", json({{"q_wxyz", {q.w(), q.x(), q.y(), q.z()}},
                                                    {"dp", {0.4, -0.2, 1.1}},
                                                    {"dv", {0.9, 0.3, -0.5}}})
                                                  .dump());
  r = RunImuconv(
      "convert --what increment_covariance --from gtsam_manifold --to forster --increment " +
          ShellQuote(d2) + " --matrix " + ShellQuote(c) + " --json",
      tmp);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const imuconv::PreintIncrement inc = imuconv::pipeline::ReadIncrementFile(d2);
  const Mat15 J = Plugins().conversion("gtsam_manifold", "forster", inc);
  const Mat15 expect_c = J * S * J.transpose();
  // Symmetrised by the command (0.5 (C + C^T)): one ulp of the largest entry apart at most.
  EXPECT_LE(MaxAbs(JsonMatrix(json::parse(r.out)["result"]["matrix"]) - expect_c),
            2 * kSameComputationUlps * MaxAbs(expect_c));
}

TEST(CliConvert, TextOutputIsALabelledTable) {
  TempDir tmp;
  const std::string state = SourcePath("examples/hover.state.json");
  const std::string m =
      tmp.write("cov.json", R"({"sigma": [1,1,1, 2,2,2, 3,3,3, 0.1,0.1,0.1, 0.2,0.2,0.2]})");
  CommandResult r =
      RunImuconv("convert --what covariance --from left --to gtsam_navstate --state " +
                     ShellQuote(state) + " --matrix " + ShellQuote(m),
                 tmp);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(Has(r.out, "covariance in gtsam_navstate (converted from left)")) << r.out;
  EXPECT_TRUE(Has(r.out, "     theta.x     theta.y     theta.z         p.x")) << r.out;
  // A negative standard deviation is refused at its entry, not squared into a covariance.
  const std::string negative =
      tmp.write("negative.json", R"({"sigma": [1,1,1, 2,2,2, 3,3,-3, 0.1,0.1,0.1, 0.2,0.2,0.2]})");
  r = RunImuconv("convert --what covariance --from left --to gtsam_navstate --state " +
                     ShellQuote(state) + " --matrix " + ShellQuote(negative),
                 tmp);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_TRUE(Has(r.err,
                  "negative.json: /sigma: entry 8 is -3: a standard deviation is not "
                  "negative"))
      << r.err;
}

TEST(CliConvert, Refusals) {
  TempDir tmp;
  const std::string state = SourcePath("examples/hover.state.json");
  const std::string good = tmp.write("good.json", MatrixJson(Mat15::Identity()).dump());
  const auto run = [&](const std::string& args) { return RunImuconv("convert " + args, tmp); };

  // Usage (exit 2): the options a --what needs, and no others.
  CommandResult r = run("--what transition --from left --to forster --state " + ShellQuote(state) +
                        " --matrix " + ShellQuote(good));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Has(r.err, "--what transition needs --state-end")) << r.err;
  r = run("--what covariance --from left --to forster --state " + ShellQuote(state));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Has(r.err, "--what covariance needs --matrix")) << r.err;
  r = run("--what increment_jacobian --from gtsam_manifold --to forster --state " +
          ShellQuote(state));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Has(r.err, "needs --increment")) << r.err;
  r = run("--what frobnicate --from left --to forster --state " + ShellQuote(state));
  EXPECT_EQ(r.exit_code, 2);
  r = run("--what covariance --to forster --state " + ShellQuote(state) + " --matrix " +
          ShellQuote(good));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(
      Has(r.err, "--from is required (or a --matrix file that declares its \"convention\")"))
      << r.err;

  // Input (exit 2), naming the file and the pointer.
  Mat15 asym = Mat15::Identity();
  asym(0, 1) = 0.5;
  const std::string bad_cov = tmp.write("asym.json", MatrixJson(asym).dump());
  r = run("--what covariance --from left --to forster --state " + ShellQuote(state) + " --matrix " +
          ShellQuote(bad_cov));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Has(r.err, bad_cov + ": (document): not a valid covariance: not symmetric")) << r.err;
  const std::string declared = tmp.write(
      "declared.json",
      json({{"convention", "gtsam_navstate"}, {"matrix", MatrixJson(Mat15::Identity())}}).dump());
  r = run("--what covariance --from left --to forster --state " + ShellQuote(state) + " --matrix " +
          ShellQuote(declared));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Has(
      r.err, declared + ": /convention: the matrix declares 'gtsam_navstate' but --from is 'left'"))
      << r.err;
  const std::string blocks =
      tmp.write("blocks.json", json({{"convention", "left"},
                                     {"blocks", {"theta", "p", "v", "ba", "bg"}},
                                     {"matrix", MatrixJson(Mat15::Identity())}})
                                   .dump());
  r = run("--what covariance --to forster --state " + ShellQuote(state) + " --matrix " +
          ShellQuote(blocks));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Has(r.err, blocks + ": /blocks: the matrix declares the block order")) << r.err;
  const std::string short_rows = tmp.write("short.json", "[[1, 2], [3, 4]]");
  r = run("--what covariance --from left --to forster --state " + ShellQuote(state) + " --matrix " +
          ShellQuote(short_rows));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Has(r.err, short_rows + ": ")) << r.err;
  r = run("--what covariance --from left --to navstate --state " + ShellQuote(state) +
          " --matrix " + ShellQuote(good));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Has(r.err, "unknown state convention 'navstate'; known: ")) << r.err;
  r = run("--what increment_covariance --from left --to forster --increment " + ShellQuote(state) +
          " --matrix " + ShellQuote(good));
  EXPECT_EQ(r.exit_code, 2);
  // The state file is not an increment: refused by the increment reader at its keys.
  EXPECT_TRUE(Has(r.err, state + ": ")) << r.err;
}

}  // namespace
