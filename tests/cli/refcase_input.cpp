// `imuconv refcase` applies the rules of `imuconv run` to its case file (FORMAT.md in
// tests/data/reference): a unit quaternion, valid covariances, non-negative noise, plausible
// timing, the documented layout; results that are not finite are refused. Every error names
// the case file and the JSON pointer, exits with 1 and writes nothing; the case file is never
// the output.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "../pipeline/pipeline_test_util.h"

namespace {
using namespace imuconv::test;
using nlohmann::json;

/// A reference case cut to 50 IMU rows (the checks do not depend on the length), modified by
/// `edit`.
std::string WriteCase(const TempDir& tmp, const std::string& name,
                      const std::function<void(json&)>& edit) {
  json c =
      json::parse(ReadText(std::string(IMUCONV_TEST_DATA_DIR) + "/reference/cases/smooth-0.json"));
  c["imu"].erase(c["imu"].begin() + 50, c["imu"].end());
  edit(c);
  return tmp.write(name, c.dump());
}

TEST(RefcaseInput, GoodCaseRuns) {
  TempDir tmp;
  const std::string c = WriteCase(tmp, "ok.json", [](json&) {});
  const CommandResult r =
      RunImuconv("refcase " + ShellQuote(c) + " -o " + ShellQuote(tmp.file("out.json")), tmp);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(json::parse(ReadText(tmp.file("out.json")))["case_id"], "smooth-0");
}

TEST(RefcaseInput, BadInputsNameThePointerAndWriteNothing) {
  TempDir tmp;
  const auto cov = [](json& c, int i, int j) -> json& { return c["cov_s_left"]["matrix"][i][j]; };
  // The edit that states the start attitude as `q` (the three quaternions that are not unit).
  const auto with_q = [](const json& q) { return [q](json& c) { c["state_s"]["q_wxyz"] = q; }; };
  struct Bad {
    std::string name;
    std::function<void(json&)> edit;
    std::string says;
  };
  const std::vector<Bad> bad = {
      {"zero_q", with_q({0, 0, 0, 0}),
       "/state_s/q_wxyz: expected a unit quaternion [w, x, y, z] (norm within 1e-6 of 1), found "
       "one of norm 0"},
      {"double_q", with_q({2, 0, 0, 0}), "/state_s/q_wxyz: expected a unit quaternion"},
      {"short_q", with_q({0.7, 0.7, 0, 0}),
       "/state_s/q_wxyz: expected a unit quaternion [w, x, y, z] (norm within 1e-6 of 1), found "
       "one of norm 0.9899494937"},
      {"indefinite_cov",
       [&](json& c) {
         // Correlation 1.5 between p_x and p_y: symmetric, positive variances, not PSD.
         const double s = std::sqrt(cov(c, 0, 0).get<double>() * cov(c, 1, 1).get<double>());
         cov(c, 0, 1) = cov(c, 1, 0) = 1.5 * s;
       },
       "/cov_s_left/matrix: not a valid covariance: not positive semi-definite: smallest "
       "eigenvalue"},
      {"asymmetric_cov", [&](json& c) { cov(c, 2, 5) = cov(c, 2, 5).get<double>() + 1.0; },
       "/cov_s_left/matrix: not a valid covariance: not symmetric"},
      {"negative_variance", [&](json& c) { cov(c, 4, 4) = -1e-6; },
       "/cov_s_left/matrix: not a valid covariance"},
      {"negative_noise", [](json& c) { c["noise"]["accel_random_walk"] = -0.1; },
       "/noise/accel_random_walk: expected a non-negative number, found -0.1"},
      {"unknown_key", [](json& c) { c["cov_s_left"]["scale"] = 2; },
       "/cov_s_left/scale: unknown key"},
      {"column_order",
       [](json& c) { c["imu_columns"] = {"t", "ax", "ay", "az", "wx", "wy", "wz"}; },
       "/imu_columns: expected [\"t\", \"wx\", \"wy\", \"wz\", \"ax\", \"ay\", \"az\"]"},
      {"block_order",
       [](json& c) {
         c["cov_s_left"]["order"] = {"theta", "p", "v", "bg", "ba"};
       },
       "/cov_s_left/order: expected"},
      {"time_back", [](json& c) { c["imu"][7][0] = c["imu"][6][0]; }, "/imu/7/0: time"},
      {"case_id", [](json& c) { c["case_id"] = 7; }, "/case_id: expected a string"},
      {"nanoseconds",
       [](json& c) {
         for (auto& row : c["imu"]) row[0] = row[0].get<double>() * 1e9;
       },
       "/imu: the median period is 5000000 s (rate 2e-07 Hz); an IMU rate is expected between 1 Hz "
       "and 100 kHz"},
      {"gap", [](json& c) { c["imu"].erase(c["imu"].begin() + 10, c["imu"].begin() + 30); },
       "/imu/10/0: gap of 0.105 s before this sample (the median period is 0.005 s"},
      // Finite inputs whose results overflow: refused like `run` refuses them, not written as null.
      {"overflow",
       [](json& c) {
         for (auto& row : c["imu"]) row[4] = 1e300;
       },
       "produced a non-finite number (output /"},
  };
  for (const auto& b : bad) {
    const std::string c = WriteCase(tmp, b.name + ".json", b.edit);
    const std::string out = tmp.file(b.name + ".out.json");
    const CommandResult r = RunImuconv("refcase " + ShellQuote(c) + " -o " + ShellQuote(out), tmp);
    EXPECT_EQ(r.exit_code, 2) << b.name << "\n" << r.err;
    EXPECT_TRUE(Has(r.err, "imuconv: error: " + c + ": " + b.says)) << b.name << "\n" << r.err;
    EXPECT_FALSE(fs::exists(out)) << b.name;
  }
  EXPECT_EQ(tmp.entries(), bad.size());  // the cases, no output, no temporary
}

TEST(RefcaseInput, TheCaseFileIsNeverTheOutput) {
  TempDir tmp;
  const std::string c = WriteCase(tmp, "case.json", [](json&) {});
  fs::create_symlink("case.json", tmp.file("link.json"));
  const std::string before = ReadText(c);
  for (const std::string& out : {c, tmp.file("link.json")}) {
    const CommandResult r = RunImuconv("refcase " + ShellQuote(c) + " -o " + ShellQuote(out), tmp);
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_TRUE(
        Has(r.err, out + ": is the same file as the case file " + c + ": refusing to overwrite it"))
        << r.err;
  }
  EXPECT_EQ(ReadText(c), before);
  EXPECT_TRUE(fs::is_symlink(tmp.file("link.json")));
  EXPECT_EQ(tmp.entries(), 2u);
}

}  // namespace
