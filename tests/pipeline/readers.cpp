// IMU and ground-truth readers: the real EuRoC slice, nanosecond precision, the generic CSV
// column map, and one specific error (file, line, expectation) per kind of malformed file.
#include <gtest/gtest.h>

#include "imuconv/pipeline/imu_reader.h"
#include "imuconv/so3.h"
#include "pipeline_test_util.h"

namespace {
using namespace imuconv;
using namespace imuconv::pipeline;
using namespace imuconv::test;

const std::string kFullEurocHeader =
    "#timestamp [ns],w_RS_S_x [rad s^-1],w_RS_S_y [rad s^-1],w_RS_S_z [rad s^-1],"
    "a_RS_S_x [m s^-2],a_RS_S_y [m s^-2],a_RS_S_z [m s^-2]\n";

/// The file `name` of `tmp`, holding `content`, is refused by `read(path)` with a message
/// that names the file and the line: it holds `path + at_line` (":<line>: <what>").
template <class Read>
void ExpectRefusedAt(TempDir& tmp, const std::string& name, const std::string& content, Read read,
                     const std::string& at_line) {
  const std::string f = tmp.write(name, content);
  const std::string msg = MessageOf<ReadError>([&] { read(f); });
  EXPECT_NE(msg.find(f + at_line), std::string::npos) << msg;
}

std::string EurocSlice() { return SourcePath("examples/data/V1_01_easy_imu0_slice.csv"); }
std::string GtSlice() {
  return SourcePath("examples/data/V1_01_easy_groundtruth_vicon2gt_slice.csv");
}

// ---- EuRoC, good files ----------------------------------------------------------------
TEST(EurocReader, RealSlice) {
  const ImuData d = ReadEurocImu(EurocSlice());
  ASSERT_EQ(d.samples.size(), 4041u);
  ASSERT_TRUE(d.origin.has_value());
  EXPECT_EQ(d.origin->nanoseconds().value(), 1403715293262142976LL);
  // First rows, compared exactly with the text of the file (same decimal -> same double).
  EXPECT_EQ(d.samples[0].t, 0.0);
  EXPECT_EQ(d.samples[0].gyro.x(), 0.50614548307835561);
  EXPECT_EQ(d.samples[0].accel.z(), -3.6202882916666663);
  // Stamps ...3267142912 - ...3262142976 = 4999936 ns: exact in int64, then one rounding.
  EXPECT_EQ(d.samples[1].t, 4999936.0 / 1e9);
  EXPECT_EQ(d.samples.back().t, 20.2);  // 20200000000 ns after the origin
  for (std::size_t i = 1; i < d.samples.size(); ++i) ASSERT_GT(d.samples[i].t, d.samples[i - 1].t);
}

TEST(EurocReader, NanosecondStepsSurviveLargeStamps) {
  // 1.4e18 ns is beyond 2^53: as a double its resolution is 256 ns. Read as int64 and made
  // relative first, a 1 ns offset on top of the 5 ms (200 Hz) steps stays exact.
  TempDir tmp;
  const std::string f = tmp.write("imu.csv", kFullEurocHeader +
                                                 "1403715273262142976,0,0,0,0,0,9.81\n"
                                                 "1403715273267142977,0,0,0,0,0,9.81\n"
                                                 "1403715273272142979,0,0,0,0,0,9.81\n");
  const ImuData d = ReadEurocImu(f);
  ASSERT_EQ(d.samples.size(), 3u);
  EXPECT_EQ(d.samples[1].t, 5000001.0 / 1e9);
  EXPECT_EQ(d.samples[2].t, 10000003.0 / 1e9);
  EXPECT_EQ(d.origin->absolute_ns(d.samples[2].t).value(), 1403715273272142979LL);
}

TEST(EurocReader, GivenOriginAndCrlf) {
  TempDir tmp;
  const std::string f = tmp.write("imu.csv",
                                  "#timestamp [ns],w_x,w_y,w_z,a_x,a_y,a_z\r\n"
                                  "2000000000, 0.1,0.2,0.3 ,1,2,3\r\n"
                                  "\r\n"
                                  "2005000000,0.1,0.2,0.3,1,2,3\r\n");
  const ImuData d = ReadEurocImu(f, 1000000000LL);
  ASSERT_EQ(d.samples.size(), 2u);
  EXPECT_EQ(d.samples[0].t, 1.0);
  EXPECT_EQ(d.samples[1].t, 1.005);
  EXPECT_EQ(d.samples[0].gyro.z(), 0.3);
}

// ---- EuRoC, malformed files: each gets its own message with file and line ------------
struct Malformed {
  const char* name;
  std::string body;    // after the header line
  std::string expect;  // substring of the message after "FILE:LINE: "
  std::size_t line;
};

void PrintTo(const Malformed& m, std::ostream* os) { *os << m.name; }

class EurocMalformed : public ::testing::TestWithParam<Malformed> {};

TEST_P(EurocMalformed, SpecificError) {
  const Malformed& m = GetParam();
  TempDir tmp;
  const std::string f = tmp.write("bad.csv", kFullEurocHeader + m.body);
  try {
    ReadEurocImu(f);
    FAIL() << "no error for " << m.name;
  } catch (const ReadError& e) {
    const std::string msg = e.what();
    EXPECT_EQ(e.file(), f);
    EXPECT_EQ(e.line(), m.line) << msg;
    EXPECT_EQ(msg.rfind(f + ":" + std::to_string(m.line) + ": ", 0), 0u) << msg;
    EXPECT_NE(msg.find(m.expect), std::string::npos) << "expected '" << m.expect << "' in: " << msg;
  }
}

INSTANTIATE_TEST_SUITE_P(
    Cases, EurocMalformed,
    ::testing::Values(Malformed{"too_few_columns", "1000,0,0,0,0,0,9.81\n2000,0,0,0,0,9.81\n",
                                "expected 7 fields separated by ',', found 6", 3},
                      Malformed{"too_many_columns", "1000,0,0,0,0,0,9.81,7\n",
                                "expected 7 fields separated by ',', found 8", 2},
                      Malformed{"non_numeric", "1000,0,abc,0,0,0,9.81\n",
                                "column 2 (w_y): expected a finite number, found 'abc'", 2},
                      Malformed{"nan", "1000,0,0,0,0,0,9.81\n2000,0,0,0,nan,0,9.81\n",
                                "column 4 (a_x): expected a finite number, found 'nan'", 3},
                      Malformed{"inf", "1000,0,0,inf,0,0,9.81\n",
                                "column 3 (w_z): expected a finite number, found 'inf'", 2},
                      Malformed{"empty_field", "1000,0,0,0,,0,9.81\n",
                                "column 4 (a_x): expected a finite number, found ''", 2},
                      Malformed{"repeated_stamp",
                                "1000,0,0,0,0,0,9.81\n2000,0,0,0,0,0,9.81\n2000,0,0,0,0,0,9.81\n",
                                "timestamp 2000 is not after the previous sample's (line 3)", 4},
                      Malformed{"decreasing_stamp", "1000,0,0,0,0,0,9.81\n999,0,0,0,0,0,9.81\n",
                                "timestamp 999 is not after the previous sample's (line 2)", 3},
                      Malformed{"fractional_stamp", "1000.5,0,0,0,0,0,9.81\n",
                                "column 0 (timestamp [ns]): expected an integer timestamp in "
                                "nanoseconds, found '1000.5'",
                                2},
                      Malformed{"stamp_overflow", "99999999999999999999,0,0,0,0,0,9.81\n",
                                "expected an integer timestamp in nanoseconds", 2},
                      Malformed{"trailing_garbage", "1000,0,0,0,0,0,9.81x\n",
                                "column 6 (a_z): expected a finite number, found '9.81x'", 2}),
    [](const auto& info) { return std::string(info.param.name); });

TEST(EurocReader, MissingAndEmptyFiles) {
  TempDir tmp;
  const std::string missing = tmp.file("nope.csv");
  std::string msg = MessageOf<ReadError>([&] { ReadEurocImu(missing); });
  EXPECT_EQ(msg, missing + ": cannot open the file for reading");
  const std::string empty = tmp.write("empty.csv", kFullEurocHeader);
  msg = MessageOf<ReadError>([&] { ReadEurocImu(empty); });
  EXPECT_EQ(msg, empty + ": contains no IMU samples");
  // A directory, and a binary file: refused rather than read without end.
  msg = MessageOf<ReadError>([&] { ReadEurocImu(tmp.path()); });
  EXPECT_EQ(msg, tmp.path() + ": is a directory, not a file");
  const std::string bin =
      tmp.write("bin.csv", kFullEurocHeader + std::string("1000,0,0,\0,0,0,9.81\n", 21));
  msg = MessageOf<ReadError>([&] { ReadEurocImu(bin); });
  EXPECT_EQ(msg, bin + ":2: contains a NUL byte; expected a text (CSV) file");
  const std::string longline = tmp.write("long.csv", kFullEurocHeader + std::string(2u << 20, '1'));
  msg = MessageOf<ReadError>([&] { ReadEurocImu(longline); });
  EXPECT_EQ(msg, longline + ":2: line is longer than 1 MiB; expected a text (CSV) file");
}

// ---- generic CSV --------------------------------------------------------------------------
TEST(CsvReader, SecondsCsvMatchesTheEurocFile) {
  // examples/data/generic_imu_seconds.csv is the first 2 s of the EuRoC slice rewritten with
  // absolute seconds (9 decimals), ';' and reordered columns. Times must agree with the
  // nanosecond file's to round-off of the fraction (tolerance 1e-15 s); values exactly.
  CsvFormat f;
  f.delimiter = ';';
  f.header_rows = 1;
  f.time_unit = TimeUnit::s;
  f.columns = {std::string("time"), 4, 5, 6, std::string("ax"), std::string("ay"),
               std::string("az")};
  const ImuData c = ReadCsvImu(SourcePath("examples/data/generic_imu_seconds.csv"), f);
  const ImuData e = ReadEurocImu(EurocSlice());
  ASSERT_EQ(c.samples.size(), 401u);
  EXPECT_EQ(c.origin->nanoseconds().value(), e.origin->nanoseconds().value());
  for (std::size_t i = 0; i < c.samples.size(); ++i) {
    ASSERT_NEAR(c.samples[i].t, e.samples[i].t, 1e-15) << i;
    ASSERT_EQ(c.samples[i].gyro, e.samples[i].gyro) << i;
    ASSERT_EQ(c.samples[i].accel, e.samples[i].accel) << i;
  }
}

TEST(CsvReader, WhitespaceMillisecondsOriginAndComments) {
  TempDir tmp;
  const std::string f = tmp.write("imu.txt",
                                  "ax ay az  t  gx gy gz\n"
                                  "-  -  -   ms rad/s rad/s rad/s\n"
                                  "0 0 9.8   1000.5  0.1 0 0\n"
                                  "% a comment line\n"
                                  "\t0 0 9.8 1003.0 0.2 0 0\n");
  CsvFormat fmt;
  fmt.whitespace_delimited = true;
  fmt.header_rows = 2;
  fmt.comment = "%";
  fmt.time_unit = TimeUnit::ms;
  fmt.time_origin = TimeValue{1000, 0.0};
  fmt.columns = {3, 4, 5, 6, 0, 1, 2};
  const ImuData d = ReadCsvImu(f, fmt);
  ASSERT_EQ(d.samples.size(), 2u);
  EXPECT_DOUBLE_EQ(d.samples[0].t, 0.5e-3);
  EXPECT_DOUBLE_EQ(d.samples[1].t, 3e-3);
  EXPECT_EQ(d.samples[1].gyro.x(), 0.2);
  EXPECT_EQ(d.samples[1].accel.z(), 9.8);
  EXPECT_EQ(d.origin->nanoseconds().value(), 1000000000LL);  // 1000 ms
}

TEST(CsvReader, SpecificErrors) {
  TempDir tmp;
  CsvFormat named;
  named.header_rows = 1;
  named.columns = {std::string("t"),  std::string("gx"), std::string("gy"), std::string("gz"),
                   std::string("ax"), std::string("ay"), std::string("az")};
  const std::string hdr = "t,gx,gy,gz,ax,ay,az\n";
  const auto read_named = [&](const std::string& f) { ReadCsvImu(f, named); };

  ExpectRefusedAt(tmp, "a.csv", "t,gyro_x,gy,gz,ax,ay,az\n0,0,0,0,0,0,0\n", read_named,
                  ":1: no column named 'gx' (for 'wx') in the header; columns: 't', 'gyro_x'");

  CsvFormat no_header = named;
  no_header.header_rows = 0;
  std::string f = tmp.write("b.csv", "0,0,0,0,0,0,0\n");
  std::string msg = MessageOf<ReadError>([&] { ReadCsvImu(f, no_header); });
  EXPECT_NE(msg.find("column 't' is given by the name 't' but the format has no header row"),
            std::string::npos)
      << msg;

  CsvFormat wide;
  wide.columns = {0, 1, 2, 3, 4, 5, 9};
  ExpectRefusedAt(
      tmp, "c.csv", "0,0,0,0,0,0,0\n", [&](const std::string& f) { ReadCsvImu(f, wide); },
      ":1: expected at least 10 fields separated by ','");

  ExpectRefusedAt(tmp, "d.csv", hdr + "0,0,0,0,0,0,0\n0.1,0,0,0,0,0\n", read_named,
                  ":3: expected 7 fields separated by ',', found 6");

  ExpectRefusedAt(tmp, "e.csv", hdr + "0,0,0,0,0,0,0\n0.1,0,0,0,0,0,0\n0.1,0,0,0,0,0,0\n",
                  read_named, ":4: timestamp 0.1 is not after the previous sample's (line 3)");

  ExpectRefusedAt(tmp, "f.csv", hdr + "0,0,0,0,0,0,0\n0.1x,0,0,0,0,0,0\n", read_named,
                  ":3: column 0 (t, 't'): expected a timestamp in s, found '0.1x'");

  ExpectRefusedAt(tmp, "g.csv", hdr + "0,0,0,0,0,NaN,0\n", read_named,
                  ":2: column 5 (ay, 'ay'): expected a finite number, found 'NaN'");

  f = tmp.write("h.csv", "");
  CsvFormat two_headers = named;
  two_headers.header_rows = 2;
  msg = MessageOf<ReadError>([&] { ReadCsvImu(f, two_headers); });
  EXPECT_NE(msg.find("expected 2 header rows, the file ends first"), std::string::npos) << msg;
}

TEST(TimeValue, ParsesExactly) {
  auto t = ParseTimeValue("1403715273.262142976");
  ASSERT_TRUE(t);
  EXPECT_EQ(t->whole, 1403715273);
  EXPECT_EQ(t->frac, 0.262142976);
  t = ParseTimeValue("-0.25");
  ASSERT_TRUE(t);
  EXPECT_EQ(t->whole, -1);
  EXPECT_EQ(t->frac, 0.75);
  t = ParseTimeValue("1.5e-3");
  ASSERT_TRUE(t);
  EXPECT_EQ(t->whole, 0);
  EXPECT_DOUBLE_EQ(t->frac, 1.5e-3);
  t = ParseTimeValue(" 42 ");
  ASSERT_TRUE(t);
  EXPECT_EQ(t->whole, 42);
  for (const char* bad : {"", "abc", "1.2.3", "nan", "inf", "1e", "--1", "0x10", "1,5"})
    EXPECT_FALSE(ParseTimeValue(bad)) << bad;
  // JSON numbers beyond int64 saturate instead of an undefined cast (UBSan catches the cast).
  EXPECT_EQ(TimeValueFromDouble(1e300).whole, 9000000000000000000LL);
  EXPECT_EQ(TimeValueFromDouble(-1e300).whole, -9000000000000000000LL);
  EXPECT_EQ(TimeValueFromDouble(-0.25).whole, -1);
  EXPECT_EQ(TimeValueFromDouble(-0.25).frac, 0.75);
  // Relative seconds: the whole parts subtract exactly before anything is rounded.
  TimeOrigin o{TimeValue{1403715273, 0.262142976}, TimeUnit::s};
  EXPECT_NEAR(o.relative_seconds(*ParseTimeValue("1403715273.267142912")), 4.999936e-3, 1e-16);
}

// ---- ground truth -----------------------------------------------------------------------
TEST(GroundTruthReader, RealSliceAndInterpolation) {
  const ImuData imu = ReadEurocImu(EurocSlice());
  const GroundTruth gt = ReadEurocGroundTruth(GtSlice(), *imu.origin);
  ASSERT_EQ(gt.t.size(), 405u);
  EXPECT_EQ(gt.t.front(), 0.0);
  // The first row of the file, compared exactly with its text.
  EXPECT_EQ(gt.x[0].p, Vec3(0.953572, 0.497809, 1.32987));
  EXPECT_EQ(gt.x[0].v, Vec3(-0.136055, -0.389991, 0.323311));
  EXPECT_EQ(gt.x[0].bg, Vec3(-0.00191464, 0.0212065, 0.0763849));
  EXPECT_EQ(gt.x[0].ba, Vec3(-0.0175313, 0.16211, 0.0891823));
  EXPECT_LT((gt.x[0].R - so3::FromQuaternionWxyz(0.429511, 0.534653, -0.615223, 0.388801)).norm(),
            1e-15);
  // Midway between two rows: p, v, b linear; R on the geodesic, half the relative angle.
  const double tm = 0.5 * (gt.t[10] + gt.t[11]);
  const auto xm = gt.at(tm);
  ASSERT_TRUE(xm);
  EXPECT_LT((xm->p - 0.5 * (gt.x[10].p + gt.x[11].p)).norm(), 1e-12);
  const Vec3 full = so3::Log(gt.x[10].R.transpose() * gt.x[11].R);
  const Vec3 half = so3::Log(gt.x[10].R.transpose() * xm->R);
  EXPECT_LT((half - 0.5 * full).norm(), 1e-12);
  EXPECT_FALSE(gt.at(-0.001));
  EXPECT_FALSE(gt.at(gt.t.back() + 1e-6));
  EXPECT_TRUE(gt.at(gt.t.back()));
}

TEST(GroundTruthReader, SpecificErrors) {
  TempDir tmp;
  const TimeOrigin o{TimeValue{0, 0.0}, TimeUnit::ns};
  const std::string hdr = "#time(ns),px,py,pz,qw,qx,qy,qz,vx,vy,vz,bwx,bwy,bwz,bax,bay,baz\n";
  const auto read = [&](const std::string& f) { ReadEurocGroundTruth(f, o); };
  ExpectRefusedAt(tmp, "a.csv", hdr + "1000,0,0,0,1,0,0,0,0,0,0,0,0,0,0,0\n", read,
                  ":2: expected 17 fields");
  ExpectRefusedAt(tmp, "b.csv", hdr + "1000,0,0,0,0.9,0,0,0,0,0,0,0,0,0,0,0,0\n", read,
                  ":2: quaternion (q_w, q_x, q_y, q_z) has norm 0.9");
  ExpectRefusedAt(
      tmp, "c.csv",
      hdr + "1000,0,0,0,1,0,0,0,0,0,0,0,0,0,0,0,0\n1000,0,0,0,1,0,0,0,0,0,0,0,0,0,0,0,0\n", read,
      ":3: timestamp 1000 is not after the previous sample's (line 2)");
  ExpectRefusedAt(tmp, "d.csv", hdr + "1000,0,0,0,1,0,0,0,0,0,x,0,0,0,0,0,0\n", read,
                  ":2: column 10 (v_z): expected a finite number, found 'x'");
  std::string f = tmp.write("e.csv", hdr + "1000,0,0,0,1,0,0,0,0,0,0,0,0,0,0,0,0\n");
  const TimeOrigin late{TimeValue{5000, 0.0},
                        TimeUnit::ns};  // rows before the origin are fine: t < 0
  EXPECT_EQ(ReadEurocGroundTruth(f, late).t.at(0), -4e-6);
  f = tmp.write("f.csv", hdr + "# only comments and blank lines\n\n");
  EXPECT_EQ(MessageOf<ReadError>([&] { ReadEurocGroundTruth(f, o); }),
            f + ": contains no ground-truth rows");
}

// Both readers go through one row loop: stamps that differ in the file but not once made
// relative in double seconds are refused at their line, in either reader, with its own noun.
TEST(RowLoop, StampsThatCollapseInDoubleSecondsAreRefusedAtTheirLine) {
  TempDir tmp;
  // 1e9 s after the origin, double seconds are 1.2e-7 s apart: 1 ns steps collapse.
  const std::string hdr = "#time(ns),px,py,pz,qw,qx,qy,qz,vx,vy,vz,bwx,bwy,bwz,bax,bay,baz\n";
  const std::string row = ",0,0,0,1,0,0,0,0,0,0,0,0,0,0,0,0\n";
  const std::string g =
      tmp.write("gt.csv", hdr + "1000000000000000000" + row + "1000000000000000001" + row);
  EXPECT_EQ(
      MessageOf<ReadError>([&] {
        ReadEurocGroundTruth(g, TimeOrigin{TimeValue{0, 0.0}, TimeUnit::s});
      }),
      g + ":3: timestamp is too close to the previous row's to be told apart in double seconds");
  // Ground truth in ns on an axis in seconds: the stamp is split into whole seconds and the
  // remainder before the difference, so the nanosecond survives (as a double, 1e18 ns + 5 ms
  // + 1 ns would round to a multiple of 128 ns).
  const std::string n =
      tmp.write("gt_ns.csv", hdr + "1000000000000000000" + row + "1000000000005000001" + row);
  const TimeOrigin near{TimeValue{1000000000, 0.0}, TimeUnit::s};
  EXPECT_EQ(ReadEurocGroundTruth(n, near).t.at(1), 5000001 / 1e9);
  CsvFormat csv;
  csv.time_origin = TimeValue{0, 0.0};
  const std::string i = tmp.write(
      "imu.csv", "1000000000.0000000001,0,0,0,0,0,9.81\n1000000000.0000000002,0,0,0,0,0,9.81\n");
  EXPECT_EQ(
      MessageOf<ReadError>([&] { ReadCsvImu(i, csv); }),
      i + ":2: timestamp is too close to the previous sample's to be told apart in double seconds");
}

}  // namespace
