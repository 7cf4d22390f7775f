// imuconv montecarlo: the bounds it judges with, its verdicts on the reference cases, its power
// against a wrong noise model, determinism across seeds and thread counts, and hostile input.
//
// The verdict (apps/montecarlo/statistics.h): consistent when both the NEES p-value (two-sided,
// chi-square with 15 N dof) and the KL p-value (Bartlett-corrected chi-square with 135 dof)
// are at least 0.5 %, so that a method whose covariance is right is called inconsistent in at
// most 1 % of seeds (tests/montecarlo/verdict_rate.cpp measures it over 200 seeds); the seeds
// here are fixed, so each test is deterministic, and the margins printed by each run (the
// reported numbers) show how far from the bounds they are.
//
// Trial counts: N = 300 over the first 5 s (1000 samples) of each case keeps the whole file at a
// few seconds in Release and well under a minute in the sanitized -O1 build. At N = 300 the NEES
// mean has standard deviation sqrt(30/300) = 0.32, the bounds are 15 -+ 0.89, and a covariance
// off by 25 % in every variance (NEES 15 / 0.8 = 18.75 or 15 * 0.8 = 12) is far outside them.
#include <gtest/gtest.h>

#include <random>
#include <string>

#include "../../apps/montecarlo/statistics.h"
#include "../pipeline/pipeline_test_util.h"
#include "imuconv_test.h"

namespace {
using namespace imuconv;
using namespace imuconv::test;
using nlohmann::json;

std::string CasePath(const std::string& id) {
  return ShellQuote(DataPath("reference/cases/" + id + ".json"));
}

CommandResult Montecarlo(const std::string& args, const TempDir& tmp) {
  return RunImuconv("montecarlo " + args, tmp);
}

/// montecarlo on the reference case `id` (tests/data/reference/cases/), with `args` after it.
CommandResult MontecarloOnCase(const std::string& id, const std::string& args, const TempDir& tmp) {
  return Montecarlo("--case " + CasePath(id) + " " + args, tmp);
}

// ---- the bounds, against printed chi-square tables (any statistics text, e.g. Abramowitz and
// Stegun table 26.8) ----
TEST(MontecarloBounds, ChiSquareQuantilesMatchTables) {
  using montecarlo::ChiSquareQuantile;
  // Wilson-Hilferty: relative error below 1e-3 for these dof in the tails (statistics.h).
  EXPECT_NEAR(ChiSquareQuantile(30, 0.975), 46.979, 46.979 * 1e-3);
  EXPECT_NEAR(ChiSquareQuantile(30, 0.025), 16.791, 16.791 * 1e-3);
  EXPECT_NEAR(ChiSquareQuantile(100, 0.99), 135.807, 135.807 * 1e-3);
  EXPECT_NEAR(ChiSquareQuantile(120, 0.99), 158.950, 158.950 * 1e-3);
  EXPECT_NEAR(ChiSquareQuantile(120, 0.95), 146.567, 146.567 * 1e-3);
  // The normal quantile the approximation rests on: 1.959964 and 2.326348 (tables, 7 digits).
  EXPECT_NEAR(montecarlo::NormalQuantile(0.975), 1.959964, 1e-6);
  EXPECT_NEAR(montecarlo::NormalQuantile(0.01), -2.326348, 1e-6);
}

TEST(MontecarloBounds, KlBoundNearBasaltsAtThousand) {
  // Basalt's own test asks KL <= 0.08 at N = 1000; the 99.5 % quantile of the Bartlett-corrected
  // likelihood-ratio statistic gives 0.0910 there (chi2_135(0.995) = 181.070, computed exactly
  // in tests/montecarlo/verdict_rate.cpp's terms; Bartlett's rho for the joint mean-and-covariance
  // test = 1 - (2 * 225 + 135 + 11) / (6 * 1000 * 18) = 0.994481).
  EXPECT_NEAR(montecarlo::KlBound(1000), 181.070 / (2000 * 0.994481), 1e-4);
  // The NEES-mean bounds (two-sided, 0.25 % in each tail) shrink as 1/sqrt(N) around 15:
  // 15 -+ 2.807034 sqrt(30/N), plus the chi-square's skew, which moves both up by
  // (2/3)(z^2 - 1)/N = 4.59/N (Cornish-Fisher's second term; 0.015 at N = 300): within 0.02.
  for (int n : {300, 1000, 5000}) {
    const auto b = montecarlo::NeesBounds(n);
    EXPECT_NEAR(b[0], 15 - 2.807034 * std::sqrt(30.0 / n), 0.02) << n;
    EXPECT_NEAR(b[1], 15 + 2.807034 * std::sqrt(30.0 / n), 0.02) << n;
  }
}

// The statistics on errors drawn exactly from the predicted Gaussian come out inside the
// bounds, and the same errors against a covariance 1.25x too large (NEES 12) do not.
TEST(MontecarloBounds, StatisticsOnExactGaussianSamples) {
  std::mt19937_64 rng(11);
  std::normal_distribution<double> n01;
  Mat15 A;
  for (int i = 0; i < 15; ++i)
    for (int j = 0; j < 15; ++j)
      A(i, j) = n01(rng) * (i == j ? 3.0 : 0.5) * std::pow(10.0, -(i / 3));
  const Mat15 Sigma = A * A.transpose();
  const Mat15 L = Sigma.llt().matrixL();
  std::vector<Vec15> errors(2000);
  for (Vec15& e : errors) {
    Vec15 z;
    for (int i = 0; i < 15; ++i) z[i] = n01(rng);
    e = L * z;
  }
  montecarlo::Statistics st;
  ASSERT_TRUE(montecarlo::ComputeStatistics(errors, Sigma, st));
  std::printf(
      "[ measured ] exact Gaussian N = 2000: NEES %.3f [%.3f, %.3f], KL %.4f (bound %.4f), rel. "
      "Frobenius %.4f\n",
      st.nees_mean, st.nees_bounds[0], st.nees_bounds[1], st.kl, st.kl_bound,
      st.relative_frobenius);
  EXPECT_GE(st.nees_mean, st.nees_bounds[0]);
  EXPECT_LE(st.nees_mean, st.nees_bounds[1]);
  EXPECT_LE(st.kl, st.kl_bound);
  ASSERT_TRUE(montecarlo::ComputeStatistics(errors, Mat15(1.25 * Sigma), st));
  EXPECT_LT(st.nees_mean, st.nees_bounds[0]);
  // Fewer than 16 errors: no full-rank sample covariance, refused.
  errors.resize(15);
  EXPECT_FALSE(montecarlo::ComputeStatistics(errors, Sigma, st));
}

// ---- the command on the reference cases ----
struct ConsistentCase {
  std::string case_id, method;
};

class MontecarloConsistent : public ::testing::TestWithParam<ConsistentCase> {};

// The project's methods whose covariance is that of continuous white noise and bias walk:
// consistent on smooth and aggressive motion and on jittered times.
TEST_P(MontecarloConsistent, Consistent) {
  const auto& p = GetParam();
  TempDir tmp;
  const CommandResult r = MontecarloOnCase(
      p.case_id, "--method " + p.method + " --trials 300 --seed 20261125 --duration 5 --json", tmp);
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  EXPECT_EQ(r.err, "");  // no progress bar when stderr is a file (nor with --json)
  const json j = json::parse(r.out);
  std::printf(
      "[ measured ] %-12s %-8s %s: rel. Frobenius %.4f, NEES %.3f [%.3f, %.3f], KL %.4f (bound "
      "%.4f)\n",
      p.case_id.c_str(), p.method.c_str(), j["convention"].get<std::string>().c_str(),
      j["relative_frobenius"].get<double>(), j["nees_mean"].get<double>(),
      j["nees_bounds"][0].get<double>(), j["nees_bounds"][1].get<double>(), j["kl"].get<double>(),
      j["kl_bound"].get<double>());
  EXPECT_EQ(j["verdict"], "consistent");
  EXPECT_EQ(j["trials"], 300);
  // These five are kernels of the core: their trials integrate the mean only (docs/montecarlo.md,
  // "Speed").
  EXPECT_EQ(j["trial_path"], "mean_only");
  // The case's samples in its first 5 s (1001 at 200 Hz; fewer on the jittered times).
  const json c = ReadJson(DataPath("reference/cases/" + p.case_id + ".json"));
  const double t0 = c["imu"][0][0].get<double>();
  int in_window = 0;
  for (const json& row : c["imu"]) in_window += row[0].get<double>() <= t0 + 5 + 1e-9;
  EXPECT_EQ(j["samples"], in_window);
  EXPECT_TRUE(j["noise_model"]["matches_prediction"].get<bool>());
  // The verdict is what the numbers say (the rule, restated).
  EXPECT_GE(j["nees_mean"].get<double>(), j["nees_bounds"][0].get<double>());
  EXPECT_LE(j["nees_mean"].get<double>(), j["nees_bounds"][1].get<double>());
  EXPECT_LE(j["kl"].get<double>(), j["kl_bound"].get<double>());
  // GTSAM's measure, not judged by the verdict: the sample variances that dominate the
  // Frobenius norm each have relative standard deviation sqrt(2/N) = 0.082 at N = 300; 3 of
  // those (0.245) bounds it with room.
  EXPECT_LT(j["relative_frobenius"].get<double>(), 0.245);
  // Every block's variance within 4 of its standard deviations sqrt(2/(3N)) = 0.047 of 1 for a
  // block trace of three variances (fewer when correlated; 0.25 is loose, and catches a block
  // off by a factor).
  for (const json& b : j["blocks"])
    EXPECT_NEAR(b["variance_ratio"].get<double>(), 1.0, 0.25) << b.dump();
}

std::vector<ConsistentCase> ConsistentCases() {
  std::vector<ConsistentCase> v;
  for (const char* c : {"smooth-0", "aggressive-0", "jitter-0"})
    for (const char* m : {"euler", "midpoint", "rk4", "manifold", "tangent"}) v.push_back({c, m});
  return v;
}

INSTANTIATE_TEST_SUITE_P(ReferenceCases, MontecarloConsistent,
                         ::testing::ValuesIn(ConsistentCases()),
                         [](const ::testing::TestParamInfo<ConsistentCase>& info) {
                           std::string s = info.param.case_id + "_" + info.param.method;
                           for (char& c : s)
                             if (c == '-') c = '_';
                           return s;
                         });

// Scored in another chart the same errors are consistent too: the error is the chart's local
// and the covariance is brought there by the registry's conversion; the blocks follow its order.
TEST(Montecarlo, ScoredInAnotherConvention) {
  TempDir tmp;
  const CommandResult r = MontecarloOnCase(
      "aggressive-0",
      "--method rk4 --convention vins_fusion --trials 300 --seed 3 --duration 5 --json", tmp);
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  const json j = json::parse(r.out);
  EXPECT_EQ(j["convention"], "vins_fusion");
  // vins_fusion's order is [p, theta, v, ba, bg] (docs/vins-fusion.md).
  const std::vector<std::string> expected{"p", "theta", "v", "ba", "bg"};
  for (int b = 0; b < 5; ++b) EXPECT_EQ(j["blocks"][b]["block"], expected[b]);
}

// Power: the same method with the simulated densities scaled (variances x4, x0.64) against the
// unscaled prediction is inconsistent, and says which way; the scaling is declared.
TEST(Montecarlo, ScaledNoiseIsInconsistent) {
  TempDir tmp;
  for (const auto& [scale, direction] :
       {std::pair<std::string, std::string>{"2", "too small"}, {"0.8", "too large"}}) {
    const CommandResult r = MontecarloOnCase(
        "smooth-0", "--method rk4 --trials 300 --seed 4 --duration 5 --json --noise-scale " + scale,
        tmp);
    ASSERT_EQ(r.exit_code, 1) << scale << r.err << r.out;
    const json j = json::parse(r.out);
    std::printf("[ measured ] noise x%s: NEES %.3f [%.3f, %.3f], KL %.4f\n", scale.c_str(),
                j["nees_mean"].get<double>(), j["nees_bounds"][0].get<double>(),
                j["nees_bounds"][1].get<double>(), j["kl"].get<double>());
    EXPECT_EQ(j["verdict"], "inconsistent");
    EXPECT_FALSE(j["noise_model"]["matches_prediction"].get<bool>());
    EXPECT_TRUE(Has(j["reasons"].dump(), direction)) << j["reasons"].dump();
    // Variances scaled by s^2 give a NEES mean near 15 s^2 (60 and 9.6): within 15 %.
    const double s = std::stod(scale);
    EXPECT_NEAR(j["nees_mean"].get<double>(), 15 * s * s, 0.15 * 15 * s * s);
  }
}

// A method that reads the noise numbers another way is not silently judged: the mismatch is
// declared in the output and in the reasons.
TEST(Montecarlo, NoiseReadingMismatchIsDeclared) {
  TempDir tmp;
  const CommandResult r = MontecarloOnCase(
      "smooth-0", "--method vins_fusion_as_configured --trials 64 --seed 1 --duration 2 --json",
      tmp);
  ASSERT_EQ(r.exit_code, 1) << r.err << r.out;
  const json j = json::parse(r.out);
  EXPECT_FALSE(j["noise_model"]["matches_prediction"].get<bool>());
  EXPECT_TRUE(Has(j["noise_model"]["note"].get<std::string>(), "MISMATCH"));
  EXPECT_TRUE(Has(j["reasons"].dump(), "mismatch"));
  // Basalt's own model is simulated for Basalt (the walk outside the samples). The model and
  // the trial path are chosen from the method before any trial runs, so the fewest trials the
  // command takes (16) over the first 0.1 s show them as well as more (64 over 2 s took about
  // 80 times the integration steps, a few seconds under ASan, for the same two fields).
  const CommandResult b = MontecarloOnCase(
      "smooth-0", "--method basalt --trials 16 --seed 1 --duration 0.1 --json", tmp);
  ASSERT_NE(b.exit_code, 2) << b.err;
  EXPECT_EQ(json::parse(b.out)["noise_model"]["simulated"], "basalt");
  EXPECT_EQ(json::parse(b.out)["trial_path"], "full");  // no mean-only kernel: the plugin per trial
  // basalt_as_configured reads the white-noise numbers as per-sample standard deviations: that
  // model is simulated, and against it the method is consistent (its variances are 1/200 of the
  // continuous model's at 200 Hz, so the continuous simulation would be off by NEES ~ 9 * 200).
  // The reading is each sample's, so jitter-0's first second (200 unequal steps) shows it as
  // well as five, at a fifth of the full-path trials (measured: NEES 15.12 over 1 s, 15.56 over
  // 5 s, both consistent).
  const CommandResult ac = MontecarloOnCase(
      "jitter-0", "--method basalt_as_configured --trials 300 --seed 2 --duration 1 --json", tmp);
  ASSERT_EQ(ac.exit_code, 0) << ac.err << ac.out;
  const json jac = json::parse(ac.out);
  EXPECT_EQ(jac["noise_model"]["simulated"], "basalt_per_sample");
  EXPECT_TRUE(jac["noise_model"]["matches_prediction"].get<bool>());
  std::printf("[ measured ] basalt_as_configured jitter-0: NEES %.3f, KL %.4f\n",
              jac["nees_mean"].get<double>(), jac["kl"].get<double>());
}

TEST(Montecarlo, DeterministicForASeedAndAnyThreadCount) {
  TempDir tmp;
  const std::string base =
      "--case " + CasePath("jitter-0") + " --method midpoint --trials 100 --duration 2 --json ";
  const CommandResult a = Montecarlo(base + "--seed 9 --threads 1", tmp);
  const CommandResult b = Montecarlo(base + "--seed 9 --threads 1", tmp);
  const CommandResult c = Montecarlo(base + "--seed 9 --threads 4", tmp);
  const CommandResult d = Montecarlo(base + "--seed 10 --threads 4", tmp);
  const CommandResult many =
      Montecarlo(base + "--seed 9 --threads 100000", tmp);  // capped, same numbers
  EXPECT_EQ(a.out, many.out) << many.err;
  ASSERT_NE(a.exit_code, 2) << a.err;
  EXPECT_EQ(a.out, b.out);
  EXPECT_EQ(a.out, c.out);  // bit-identical numbers in the printed JSON
  EXPECT_NE(a.out, d.out);
  EXPECT_EQ(json::parse(a.out)["seed"], 9);
}

TEST(Montecarlo, HostileInputExitsTwoWithAClearMessage) {
  TempDir tmp;
  const std::string ok_case = CasePath("smooth-0");
  const std::string tail = " --trials 32 --seed 1 --duration 1";
  CommandResult r =
      Montecarlo("--case " + ShellQuote(tmp.file("missing.json")) + " --method rk4" + tail, tmp);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Has(r.err, "missing.json")) << r.err;

  r = Montecarlo("--case " + ok_case + " --method rk5" + tail, tmp);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Has(r.err, "unknown method") && Has(r.err, "rk4") && Has(r.err, "manifold")) << r.err;

  r = Montecarlo("--case " + ok_case + " --method rk4 --convention gtsam_navstate" + tail, tmp);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Has(r.err, "unknown increment convention") && Has(r.err, "is a state convention"))
      << r.err;

  for (const char* n : {"1", "15", "0", "-3", "20000000"}) {
    r = Montecarlo("--case " + ok_case + " --method rk4 --seed 1 --trials " + std::string(n), tmp);
    EXPECT_EQ(r.exit_code, 2) << n;
    EXPECT_TRUE(Has(r.err, "--trials")) << r.err;
  }

  r = Montecarlo("--case " + ok_case + " --method rk4 --trials 32", tmp);  // no --seed
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Has(r.err, "--seed")) << r.err;

  // A negative seed is refused, not wrapped to 2^64 - 1.
  r = Montecarlo("--case " + ok_case + " --method rk4 --trials 32 --seed -1", tmp);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Has(r.err, "--seed")) << r.err;

  // A case without its IMU rows, and one whose noise is zero (no covariance to compare with).
  json c = ReadJson(DataPath("reference/cases/smooth-0.json"));
  json no_imu = c;
  no_imu.erase("imu");
  r = Montecarlo(
      "--case " + ShellQuote(tmp.write("no_imu.json", no_imu.dump())) + " --method rk4" + tail,
      tmp);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Has(r.err, "no_imu.json") && Has(r.err, "imu")) << r.err;

  json quiet = c;
  for (auto& [k, v] : quiet["noise"].items()) v = 0.0;
  r = Montecarlo(
      "--case " + ShellQuote(tmp.write("quiet.json", quiet.dump())) + " --method rk4" + tail, tmp);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Has(r.err, "not positive definite")) << r.err;

  r = Montecarlo(
      "--case " + ShellQuote(tmp.write("broken.json", "{\"imu\": [")) + " --method rk4" + tail,
      tmp);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Has(r.err, "broken.json")) << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
}

}  // namespace
