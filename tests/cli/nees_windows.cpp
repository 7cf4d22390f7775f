// imuconv nees: which windows are fitted. A window must hold at least one IMU sample
// (docs/timing.md, the rule run and check apply to every interval): a window length shorter
// than the IMU's sample period is refused (exit 2, naming --windows, the length and the
// period), as is one lying between two ordinary samples; a window reaching into a gap of the
// data (a pipeline with allow_gaps) is skipped, counted in the output and warned about, never
// fitted. And the number of windows is bounded over all the lengths together, refused before
// any is propagated.
//
// Every run here is refused, or propagates two windows: well under a second.
#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "../pipeline/pipeline_test_util.h"
#include "euroc_slice.h"
#include "imuconv_test.h"

namespace {
using namespace imuconv;
using namespace imuconv::test;
using nlohmann::json;

std::string SliceArgsRk4(const TempDir& tmp) {
  return "--imu " + ShellQuote(kEurocSliceImu) + " --ground-truth " +
         ShellQuote(kEurocSliceGroundTruth) + " --noise " +
         ShellQuote(tmp.write("noise.json", kEurocNoise.dump())) + " --method rk4";
}

// 1 ms windows on 200 Hz samples (5 ms apart): most lie between two samples.
TEST(NeesWindows, LengthShorterThanTheSamplePeriodIsRefused) {
  const TempDir tmp;
  const CommandResult r = RunImuconv("nees " + SliceArgsRk4(tmp) + " --windows 0.5,0.001", tmp);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Has(r.err, "--windows: 0.001 s is shorter than the IMU's sample period, ") &&
              Has(r.err, " s (median)") && Has(r.err, "interpolation only"))
      << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;

  // Windows of one median period starting at multiples of it: the slice's stamps jitter by tens
  // of nanoseconds about 5 ms, so some window lies strictly between two ordinary samples (no
  // gap): refused, naming that window.
  const CommandResult at_period = RunImuconv("nees " + SliceArgsRk4(tmp) + " --windows 0.005", tmp);
  EXPECT_EQ(at_period.exit_code, 2);
  EXPECT_TRUE(Has(at_period.err, "--windows: the window [") &&
              Has(at_period.err, "of 0.005 s holds no IMU sample: it lies between two samples"))
      << at_period.err;
  EXPECT_TRUE(at_period.out.empty()) << at_period.out;
}

// Three lengths of a stride typo (2.05e-5 s on 20 s of data): some 980 000 windows each, under
// the bound one at a time, three times it together. Refused at once, naming both options.
TEST(NeesWindows, TooManyWindowsOverAllLengthsAreRefused) {
  const TempDir tmp;
  const CommandResult r = RunImuconv(
      "nees " + SliceArgsRk4(tmp) + " --windows 0.01,0.011,0.012 --stride 0.0000205", tmp);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(Has(r.err, "--windows, --stride: 3 window length(s) at a stride of 2.05e-05 s") &&
              Has(r.err, "more than 1000000 in all"))
      << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
}

/// Lines 1..rows of `text` (after its header line 0), then the same rows again with their
/// nanosecond stamps (the first field) moved by `shift_ns`: the data, a gap, the data again.
std::string RowsGapRows(const std::string& text, std::size_t rows, std::int64_t shift_ns) {
  std::vector<std::string> lines;
  std::size_t at = 0;
  for (std::size_t next; (next = text.find('\n', at)) != std::string::npos; at = next + 1)
    lines.push_back(text.substr(at, next - at));
  std::string out = lines.at(0) + "\n";
  for (std::size_t i = 1; i <= rows; ++i) out += lines.at(i) + "\n";
  for (std::size_t i = 1; i <= rows; ++i) {
    const std::size_t comma = lines.at(i).find(',');
    out += std::to_string(std::stoll(lines[i].substr(0, comma)) + shift_ns) +
           lines[i].substr(comma) + "\n";
  }
  return out;
}

// 2 s of data (401 IMU rows at 200 Hz, 41 ground-truth rows at 20 Hz), a gap of 1e6 s, the same
// 2 s again (the first sample after the gap at exactly 1e6 s, the shift being whole seconds).
TEST(NeesWindows, WindowsReachingIntoAGapAreSkippedAndCounted) {
  const TempDir tmp;
  constexpr std::int64_t kGapNs = 1000000000000000;  // 1e6 s
  const std::string imu =
      tmp.write("imu_gap.csv", RowsGapRows(ReadText(kEurocSliceImu), 401, kGapNs));
  const std::string gt =
      tmp.write("gt_gap.csv", RowsGapRows(ReadText(kEurocSliceGroundTruth), 41, kGapNs));
  json p = NeesPipeline({{"format", "euroc"}, {"path", imu}, {"allow_gaps", true}});
  p["ground_truth"] = {{"format", "euroc"}, {"path", gt}, {"allow_gaps", true}};
  const std::string pipeline = tmp.write("gap.json", p.dump());

  // Windows of 0.5 s every 500 s, from 0 while they end by the data's end (1e6 + 2 s): starts
  // 0, 500, ..., 1e6, 2001 windows. [0, 0.5] lies in the first 2 s and [1e6, 1e6 + 0.5] in the
  // last; the 1999 between lie in the gap.
  const CommandResult r = RunImuconv(
      "nees --pipeline " + ShellQuote(pipeline) + " --windows 0.5 --stride 500 --method rk4 --json",
      tmp);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json out = json::parse(r.out);
  const json& w = out["windows"][0];
  EXPECT_EQ(w["count"].get<std::size_t>(), 2u);
  EXPECT_EQ(w["nees"].size(), 2u);
  EXPECT_EQ(w["skipped_in_gap"].get<std::size_t>(), 1999u);
  EXPECT_EQ(w["t_start"][0].get<double>(), 0.0);
  EXPECT_EQ(w["t_start"][1].get<double>(), 1e6);
  const std::string warning = "0.5 s windows: 1999 of 2001 reach into a gap in the data";
  EXPECT_TRUE(Has(r.err, warning)) << r.err;
  ASSERT_TRUE(out.contains("warnings")) << r.out;
  bool warned = false;
  for (const auto& s : out["warnings"]) warned = warned || Has(s.get<std::string>(), warning);
  EXPECT_TRUE(warned) << out["warnings"].dump();

  // Windows of 1000 s every 1000 s: [0, 1000] holds the first 2 s of samples and then the gap,
  // [999000, 1e6] the gap and the first sample after it, the 998 between only the gap. Every
  // one reaches into the gap: nothing to fit, refused.
  const CommandResult all =
      RunImuconv("nees --pipeline " + ShellQuote(pipeline) + " --windows 1000 --method rk4", tmp);
  EXPECT_EQ(all.exit_code, 2);
  EXPECT_TRUE(Has(all.err, "--windows: all 1000 windows of 1000 s reach into a gap of the data"))
      << all.err;
  EXPECT_TRUE(all.out.empty()) << all.out;
}

}  // namespace
