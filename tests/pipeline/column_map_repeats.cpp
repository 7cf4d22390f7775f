// A CSV IMU's column map must give each of t, wx, ..., az its own column: one column read for
// two axes (the same index twice, the same name twice, a name and an index that meet, or a
// header that holds the mapped name twice) would be a wrong answer given in silence.
#include <gtest/gtest.h>

#include "imuconv/pipeline/imu_reader.h"
#include "imuconv/pipeline/pipeline.h"
#include "issue_at.h"
#include "pipeline_test_util.h"

// A named namespace, not an anonymous one: the tests are compiled in unity batches, where
// this file's helpers and using-directives must not meet another file's.
namespace column_map_repeats_test {
using namespace imuconv;
using namespace imuconv::pipeline;
using namespace imuconv::test;
using nlohmann::json;

/// A pipeline reading examples/data/generic_imu_seconds.csv (header
/// "time;ax;ay;az;gx;gy;gz") with the column map `columns`, and one preintegrate task.
json CsvPipeline(const json& columns) {
  return {{"noise",
           {{"gyro_noise_density", 1.6968e-04},
            {"accel_noise_density", 2.0e-3},
            {"gyro_random_walk", 1.9393e-05},
            {"accel_random_walk", 3.0e-3}}},
          {"imu",
           {{"format", "csv"},
            {"path", SourcePath("examples/data/generic_imu_seconds.csv")},
            {"delimiter", ";"},
            {"header_rows", 1},
            {"time_unit", "s"},
            {"columns", columns}}},
          {"tasks",
           {{{"type", "preintegrate"},
             {"name", "kf"},
             {"method", {{"preintegrator", "tangent"}}},
             {"keyframes", {0.0, 0.5, 1.0}}}}}};
}

const json kGoodColumns = {{"t", "time"}, {"ax", "ax"}, {"ay", "ay"}, {"az", "az"},
                           {"wx", 4},     {"wy", 5},    {"wz", 6}};

TEST(ColumnMapRepeats, TheGoodMapParses) {
  EXPECT_TRUE(ReadingIssues(CsvPipeline(kGoodColumns)).empty());
}

TEST(ColumnMapRepeats, OneIndexForTwoAxesIsRefusedAtThePointer) {
  json cols = kGoodColumns;
  cols["wy"] = 4;
  const auto is = ReadingIssues(CsvPipeline(cols));
  EXPECT_ISSUE(is, "/imu/columns/wy", "column 4 is already used for 'wx'");
  EXPECT_EQ(is.size(), 1u);
}

TEST(ColumnMapRepeats, OneNameForTwoAxesIsRefusedAtThePointer) {
  json cols = kGoodColumns;
  cols["az"] = "ax";
  EXPECT_ISSUE(ReadingIssues(CsvPipeline(cols)), "/imu/columns/az",
               "the column named 'ax' is already used for 'ax'");
}

TEST(ColumnMapRepeats, HeaderNamingTheMappedColumnTwiceIsAmbiguous) {
  TempDir tmp;
  const std::string f =
      tmp.write("imu.csv", "time;a;a;a;g;g;g\n0;0;0;9.8;0;0;0\n0.005;0;0;9.8;0;0;0\n");
  CsvFormat fmt;
  fmt.delimiter = ';';
  fmt.header_rows = 1;
  fmt.columns = {std::string("time"), std::string("g"), 5, 6, std::string("a"), 2, 3};
  EXPECT_EQ(MessageOf<ReadError>([&] { ReadCsvImu(f, fmt); }),
            f + ":1: the header names 'g' twice (columns 4 and 5), so the column for 'wx' is "
                "ambiguous; give its index instead");
  // A repeated name that the map does not use is no ambiguity: the file is read.
  fmt.columns = {std::string("time"), 4, 5, 6, 1, 2, 3};
  EXPECT_EQ(ReadCsvImu(f, fmt).samples.size(), 2u);
}

TEST(ColumnMapRepeats, NameAndIndexMeetingInOneColumnAreRefusedWithTheHeaderLine) {
  TempDir tmp;
  const std::string f = tmp.write("imu.csv", "time,ax,ay,az,gx,gy,gz\n0,0,0,9.8,0,0,0\n");
  CsvFormat fmt;
  fmt.header_rows = 1;
  // 'wx' by name and 'az' by index: the parser cannot see that they meet, the reader must.
  fmt.columns = {std::string("time"), std::string("gx"), 5, 6, 1, 2, 4};
  EXPECT_EQ(MessageOf<ReadError>([&] { ReadCsvImu(f, fmt); }),
            f + ":1: the column map reads column 4 for both 'wx' and 'az' (wx, 'gx'; az, 'gx'); "
                "each of t, wx, wy, wz, ax, ay, az needs its own column");
}

TEST(ColumnMapRepeats, TheCommandExitsTwoAndWritesNothing) {
  TempDir tmp;
  json cols = kGoodColumns;
  cols["wy"] = 4;
  const std::string p = tmp.write("c.json", CsvPipeline(cols).dump());
  const CommandResult r =
      RunImuconv("run " + ShellQuote(p) + " -o " + ShellQuote(tmp.file("o.json")), tmp);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find(p + ": /imu/columns/wy: column 4 is already used for 'wx'"),
            std::string::npos)
      << r.err;
  EXPECT_FALSE(std::filesystem::exists(tmp.file("o.json")));
}

}  // namespace column_map_repeats_test
