// The report pages of check, montecarlo and nees (apps/report/pages/) and what they draw:
// check's entrywise matrices must be the differences its summary reports (their max is the
// summary's max, to the bit), a covariance doubled must show d = 1 on its diagonal, and each page
// must hold its figures.
#include <gtest/gtest.h>

#include <string>

#include "../../apps/report/pages/pages.h"
#include "../pipeline/pipeline_test_util.h"
#include "imuconv/check/case_input.h"
#include "imuconv/check/check.h"
#include "imuconv/pipeline/measurement.h"
#include "imuconv_test.h"
#include "montecarlo.h"
#include "nees.h"
#include "text_contains.h"

namespace {
using namespace imuconv;
using namespace imuconv::test;

const std::string kCase = "reference/cases/smooth-0.json";
const std::string kMeasurements =
    SourcePath("examples/data/gtsam_smooth0_manifold.measurements.json");

check::CheckResult Check(const std::string& meas_path) {
  const check::CaseInput input = check::ReadCaseFile(DataPath(kCase));
  return check::RunCheck(Plugins(), input,
                         pipeline::ReadDeclaredMeasurementFile(meas_path, Plugins()), meas_path);
}

TEST(CheckPage, EntrywiseMatricesAreTheDifferencesTheSummaryReports) {
  const check::CheckResult r = Check(kMeasurements);
  ASSERT_EQ(r.measurements.size(), 1u);
  const check::MeasurementCheck& m = r.measurements[0];
  const check::BestEntries& e = m.best_entries;
  ASSERT_EQ(e.J_bias.rows(), 9);
  ASSERT_EQ(e.J_bias.cols(), 6);
  ASSERT_EQ(e.cov.rows(), 15);
  ASSERT_EQ(e.cov.cols(), 15);
  // The same per-entry function makes both (difference.cpp): the max is equal to the bit; the
  // mean is summed in another order, so equal to round-off (1e-12 relative, 225 terms).
  EXPECT_EQ(e.J_bias.maxCoeff(), m.best.J_bias.max);
  EXPECT_EQ(e.cov.maxCoeff(), m.best.cov.max);
  EXPECT_NEAR(e.J_bias.mean(), m.best.J_bias.mean, 1e-12 * m.best.J_bias.mean + 1e-300);
  EXPECT_NEAR(e.cov.mean(), m.best.cov.mean, 1e-12 * m.best.cov.mean + 1e-300);
  // GTSAM's J_bias rows are its manifold chart's [theta, p, v].
  EXPECT_EQ(e.J_bias_rows, (std::vector<std::string>{"theta", "p", "v"}));

  const std::string html = report::CheckPage(r, {{"measurements", kMeasurements}}).Render();
  EXPECT_EQ(Count(html, "class=\"heatmap\""), 2u);
  EXPECT_EQ(Count(html, "class=\"cell\""), 54u + 225u);
  // Both maps on check's fixed range, each with its tolerance (verdict.cpp: 1e-2 for both), and
  // the verdict badge at the top.
  EXPECT_EQ(Count(html, "data-scale-min=\"1e-16\" data-scale-max=\"100\" data-tolerance=\"0.01\""),
            2u);
  EXPECT_EQ(Count(html, "data-verdict=\""), 1u);
  EXPECT_LT(html.find("data-verdict=\""), html.find("<h2>"));
}

TEST(CheckPage, ADoubledCovarianceShowsOneOnItsDiagonal) {
  nlohmann::json meas = ReadJson(kMeasurements);
  for (auto& row : meas["measurements"][0]["cov"]["matrix"])
    for (auto& x : row) x = 2.0 * x.get<double>();
  TempDir tmp;
  const std::string path = tmp.write("doubled.json", meas.dump());
  const check::CheckResult r = Check(path);
  ASSERT_EQ(r.measurements.size(), 1u);
  const Eigen::MatrixXd& d = r.measurements[0].best_entries.cov;
  ASSERT_EQ(d.rows(), 15);
  // |2K_ii - K_ii| / K_ii = 1 on the correlation scale, whatever explanation is nearest for the
  // off-diagonal entries (tests/cli/check.cpp bounds the max the same way: [0.99, 1.01]).
  for (int i = 0; i < 15; ++i) EXPECT_NEAR(d(i, i), 1.0, 0.01) << i;
}

TEST(MontecarloPage, HeatmapsOfTheSampleCovarianceAgainstThePrediction) {
  montecarlo::Result r;
  r.method = "euler";
  r.convention = "preint_reference";
  r.trials = 100;
  r.predicted = Mat15::Identity();
  r.stats.sample_cov = 1.1 * Mat15::Identity();
  for (const char* b : {"theta", "p", "v", "bg", "ba"})
    r.blocks.push_back({b, 1.1, {1.1, 1.1, 1.1}});
  r.verdict = montecarlo::Verdict::inconsistent;
  r.reasons = {"NEES mean 16.5 outside its 95% chi-square bounds"};
  const std::string html = report::MontecarloPage(r, {{"case", "c.json"}}).Render();
  EXPECT_EQ(Count(html, "class=\"heatmap\""), 2u);
  EXPECT_EQ(Count(html, "<div class=\"verdict\" data-verdict=\"inconsistent\">"), 1u);
  EXPECT_EQ(Count(html, "NEES mean 16.5 outside its 95% chi-square bounds</span>"), 1u);
  // Standardized, by hand: (1.1 - 1) / sqrt((1 + 1) / 99) = 0.70356 on the diagonal; off it
  // (0 - 0) / sqrt(1 / 99) = 0, in the calm middle.
  EXPECT_EQ(Count(html, "theta.x, theta.x: z = 0.704 (within the tolerance 3)<"), 1u);
  EXPECT_EQ(Count(html,
                  "data-scale-kind=\"signed\" data-scale-min=\"-5\" data-scale-max=\"5\" "
                  "data-tolerance=\"3\""),
            1u);
  // Correlation scale: |1.1 - 1| / 1 = 0.1 on the diagonal, within 3 sqrt(2/99) = 0.426; the 210
  // exact zeros off it drawn as agreement (a dot each), not as blank cells.
  EXPECT_EQ(Count(html, "theta.x, theta.x: d = 0.1 (within the tolerance 0.426)<"), 1u);
  EXPECT_EQ(Count(html, ">0 (exact) \u00d7210</text>"), 1u);
  EXPECT_EQ(Count(html, "class=\"zero-mark\""), 210u);
  // Variance ratios 1.1 within 1 +- 2 sqrt(2/99) = [0.716, 1.28] on every axis.
  EXPECT_EQ(Count(html, "<td>all inside</td>"), 5u);
  EXPECT_EQ(Count(html, "class=\"chart\""), 0u);  // no trials' NEES in this result: no histogram
  // With them: one histogram, its bars and the chi-square(15) counts as a line.
  r.trial_nees = {3.0, 14.0, 15.0, 16.0, 60.0};
  const std::string with = report::MontecarloPage(r, {}).Render();
  EXPECT_EQ(Count(with, "class=\"chart\""), 1u);
  EXPECT_EQ(Count(with, "Per-trial NEES against chi-square(15)"), 2u);  // title text and aria-label
  EXPECT_EQ(Count(with, "(5 trials) in 30 bins"), 1u);
}

nees::Result NeesResult(bool keep_errors) {
  nees::Result r;
  r.method = "rk4";
  r.convention = "left";
  r.chi2 = nees::ChiSquare9();
  for (double length : {0.5, 1.0}) {
    nees::WindowLengthResult w;
    w.length = w.stride = length;
    for (int i = 0; i < 20; ++i) {
      w.t_start.push_back(i * length);
      w.nees.push_back(1.0 + i);
      if (keep_errors) {
        w.error.push_back(Vec9::Constant(0.01 * (i % 3 - 1)));
        w.sigma.push_back(Vec9::Constant(0.004));
      }
    }
    r.windows.push_back(w);
  }
  return r;
}

TEST(NeesPage, NeesAgainstChiSquareAndEachErrorWithItsBand) {
  const std::string html = report::NeesPage(NeesResult(true), {{"imu", "imu.csv"}}).Render();
  // Per window length: NEES over time, its histogram, nine error components.
  EXPECT_EQ(Count(html, "class=\"chart\""), 22u);
  EXPECT_EQ(Count(html, "class=\"band\""), 18u);
  // Errors of -0.01, 0, 0.01 against 3 sigma = 0.012: none outside.
  EXPECT_EQ(Count(html, ": 0 of 20 windows outside"), 18u);
  EXPECT_EQ(Count(html, "not judged (a sensor"),
            2u + 2u);  // summary rows and sections: no components given
  const std::string without = report::NeesPage(NeesResult(false), {}).Render();
  EXPECT_EQ(Count(without, "class=\"chart\""), 4u);
  EXPECT_EQ(Count(without, "The errors were not kept"), 2u);
}

TEST(NeesPage, FactorsAndOffsetFlagsBesideTheirPlots) {
  nees::Result r = NeesResult(true);
  for (auto& w : r.windows) {
    w.factor = 8.0;
    w.factor_gyro = 7.0;
    w.factor_accel = 10.5;
    w.components.resize(9);
    for (int i = 0; i < 9; ++i) {
      w.components[i].name = nees::ComponentNames()[static_cast<std::size_t>(i)];
      w.components[i].mean_standardized = i == 6 ? 1.9 : 0.1;
      w.components[i].rms_standardized = i == 6 ? 2.0 : 1.0;
      w.components[i].offset = i == 6;
    }
  }
  const std::string html = report::NeesPage(r, {}).Render();
  EXPECT_EQ(Count(html, "<td>7</td><td>10.5</td><td>v.x (mean 1.9)</td>"), 2u);
  EXPECT_EQ(Count(html, "Factors: k (all) 8, k_gyro 7, k_accel 10.5. Offsets: v.x (mean 1.9)."),
            2u);
  // The flag on the v.x figure itself and in its caption, on no other.
  EXPECT_EQ(Count(html, "\u2014 OFFSET (mean 1.9 sigma)"),
            2u * 2u);  // the chart's title text and aria-label
  EXPECT_EQ(Count(html, "OFFSET: the mean dominates the spread."), 2u);
}

}  // namespace
