// Inputs a careless or hostile user gives the readers (issue 9): a column index past the
// header, gaps and wrong time units, a FIFO or a device as an input, a kept time range,
// duplicate JSON keys, thousands of problems in one document, and text that must be escaped.
// Every case asserts the exact file:line or file: pointer of its message.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <functional>
#include <thread>

#include "imuconv/pipeline/imu_reader.h"
#include "imuconv/pipeline/json_parse.h"
#include "pipeline_test_util.h"

namespace {
using namespace imuconv;
using namespace imuconv::pipeline;
using namespace imuconv::test;

const std::string kShortEurocHeader = "#timestamp [ns],w_x,w_y,w_z,a_x,a_y,a_z\n";

// EuRoC rows from t0 (ns) every `period` ns; row i (0-based) is preceded by an extra `gap_ns`
// when i == gap_at. The first data row is line 2 of the file.
std::string EurocRows(std::size_t n, std::int64_t t0, std::int64_t period,
                      std::size_t gap_at = SIZE_MAX, std::int64_t gap_ns = 0) {
  std::string s;
  std::int64_t t = t0;
  for (std::size_t i = 0; i < n; ++i) {
    if (i == gap_at) t += gap_ns;
    s += std::to_string(t) + ",0.01,0.02,0.03,0.1,0.2,9.81\n";
    t += period;
  }
  return s;
}

// Ground-truth rows (identity attitude) every `period` ns, with a hole before row gap_at.
std::string GtRows(std::size_t n, std::int64_t t0, std::int64_t period,
                   std::size_t gap_at = SIZE_MAX, std::int64_t gap_ns = 0) {
  std::string s = "#time(ns),px,py,pz,qw,qx,qy,qz,vx,vy,vz,bwx,bwy,bwz,bax,bay,baz\n";
  std::int64_t t = t0;
  for (std::size_t i = 0; i < n; ++i) {
    if (i == gap_at) t += gap_ns;
    s += std::to_string(t) + "," + std::to_string(i) + ",0,0,1,0,0,0,0,0,0,0,0,0,0,0,0\n";
    t += period;
  }
  return s;
}

/// The message ReadCsvImu refuses `path` with under `fmt` ("" if it reads it).
std::string CsvImuError(const std::string& path, const CsvFormat& fmt) {
  return MessageOf<ReadError>([&] { ReadCsvImu(path, fmt); });
}

/// The message ReadEurocImu refuses `path` with under `options` ("" if it reads it).
std::string EurocImuError(const std::string& path, const ReadOptions& options = {}) {
  return MessageOf<ReadError>([&] { ReadEurocImu(path, std::nullopt, options); });
}

// ---- 1. column indices past the width of the header or of the rows -----------------------
TEST(ColumnMap, IndexPastTheHeaderIsAnErrorNotAReadPastTheEnd) {
  // Before the fix the width check ran only when no header had fixed the field count, so
  // index 9 read fields[9] of a 7-field row (a heap read past the end).
  TempDir tmp;
  const std::string f =
      tmp.write("imu.csv", "t,gx,gy,gz,ax,ay,az\n0,0,0,0,0,0,9.8\n0.005,0,0,0,0,0,9.8\n");
  CsvFormat fmt;
  fmt.header_rows = 1;
  fmt.columns = {0, 1, 2, 3, 4, 5, 9};
  EXPECT_EQ(CsvImuError(f, fmt),
            f + ":1: the column map uses index 9 (for 'az') but the header has 7 columns");
  // The widest column is named whichever it is, and a header below a comment-free second row.
  fmt.columns = {0, 1, 2, 3, 100000, 5, 6};
  fmt.header_rows = 2;
  const std::string g = tmp.write("imu2.csv", "t,gx,gy,gz,ax,ay,az\nunits\n0,0,0,0,0,0,9.8\n");
  EXPECT_EQ(CsvImuError(g, fmt),
            g + ":1: the column map uses index 100000 (for 'ax') but the header has 7 columns");
  // Names and indices mixed: the index is still checked against the header.
  fmt.header_rows = 1;
  fmt.columns = {std::string("t"), 1, 2, 3, 4, 5, 7};
  EXPECT_EQ(CsvImuError(f, fmt),
            f + ":1: the column map uses index 7 (for 'az') but the header has 7 columns");
}

TEST(ColumnMap, IndexPastTheFirstRowWithoutHeader) {
  TempDir tmp;
  const std::string f = tmp.write("imu.csv", "0;0;0;0;0;0;9.8\n");
  CsvFormat fmt;
  fmt.delimiter = ';';
  fmt.columns = {0, 1, 2, 3, 4, 5, 9};
  EXPECT_EQ(CsvImuError(f, fmt),
            f + ":1: expected at least 10 fields separated by ';' (the column map uses index 9 for "
                "'az'), found 7");
  // A later row narrower than the first: refused before any field of it is read.
  const std::string g = tmp.write("imu2.csv", "0 0 0 0 0 0 9.8 1 2 3\n0.005 0 0\n");
  fmt.whitespace_delimited = true;
  EXPECT_EQ(CsvImuError(g, fmt), g + ":2: expected 10 fields separated by whitespace, found 3");
}

TEST(ColumnMap, BlankHeaderWithNamedColumns) {
  TempDir tmp;
  const std::string f = tmp.write("imu.csv", "   \n0 0 0 0 0 0 9.8\n");
  CsvFormat fmt;
  fmt.whitespace_delimited = true;
  fmt.header_rows = 1;
  fmt.columns = {std::string("t"), 1, 2, 3, 4, 5, 6};
  EXPECT_EQ(CsvImuError(f, fmt),
            f + ":1: no column named 't' (for 't') in the header; columns: none (the header row is "
                "blank)");
}

// ---- 2. IMU timing: gaps and rates ---------------------------------------------------------
TEST(ImuTiming, GapIsAnErrorAtTheLineAfterIt) {
  TempDir tmp;
  // 200 Hz, and 0.5 s missing before row 100 (line 102).
  const std::string f =
      tmp.write("imu.csv", kShortEurocHeader + EurocRows(300, 1000000000, 5000000, 100, 495000000));
  EXPECT_EQ(EurocImuError(f),
            f + ":102: gap of 0.5 s before this sample (the median period is 0.005 s; limit 10 x "
                "median = 0.05 s); "
                "set \"allow_gaps\": true in the IMU source to integrate across it");
  // Allowed, or under a larger factor (0.5 s = 100 x 0.005 s): read.
  ReadOptions allow;
  allow.timing.allow_gaps = true;
  EXPECT_EQ(ReadEurocImu(f, std::nullopt, allow).samples.size(), 300u);
  ReadOptions factor;
  factor.timing.max_gap_factor = 101;
  EXPECT_EQ(ReadEurocImu(f, std::nullopt, factor).samples.size(), 300u);
  factor.timing.max_gap_factor = 99;
  EXPECT_NE(EurocImuError(f, factor).find(f + ":102: gap of 0.5 s"), std::string::npos);
}

TEST(ImuTiming, GapInGenericCsv) {
  TempDir tmp;
  std::string body = "t,gx,gy,gz,ax,ay,az\n";
  for (int i = 0; i < 50; ++i) body += std::to_string(0.01 * i) + ",0,0,0,0,0,9.8\n";
  body += "3600.5,0,0,0,0,0,9.8\n";  // line 52: an hour later
  const std::string f = tmp.write("imu.csv", body);
  CsvFormat fmt;
  fmt.header_rows = 1;
  EXPECT_EQ(CsvImuError(f, fmt),
            f + ":52: gap of 3600.01 s before this sample (the median period is 0.01 s; limit 10 x "
                "median = 0.1 s); "
                "set \"allow_gaps\": true in the IMU source to integrate across it");
}

TEST(ImuTiming, NanosecondStampsDeclaredAsSecondsNameTheUnit) {
  TempDir tmp;
  std::string body;
  for (int i = 0; i < 20; ++i)
    body += std::to_string(1403715273262142976LL + 5000000LL * i) + ",0,0,0,0,0,9.8\n";
  const std::string f = tmp.write("imu.csv", body);
  CsvFormat fmt;  // time_unit s
  EXPECT_EQ(CsvImuError(f, fmt),
            f + ": the median period is 5e+06 s (rate 2e-07 Hz); the timestamps look like "
                "nanoseconds: set time_unit to "
                "\"ns\" (an IMU rate is expected between 1 Hz and 100 kHz)");
  fmt.time_unit = TimeUnit::ns;
  EXPECT_EQ(ReadCsvImu(f, fmt).samples.size(), 20u);
  // Milliseconds declared as seconds: 5 s periods.
  std::string ms;
  for (int i = 0; i < 20; ++i) ms += std::to_string(1000000 + 5 * i) + ",0,0,0,0,0,9.8\n";
  const std::string g = tmp.write("ms.csv", ms);
  fmt.time_unit = TimeUnit::s;
  EXPECT_NE(CsvImuError(g, fmt).find(
                g + ": the median period is 5 s (rate 0.2 Hz); the timestamps look like "
                    "milliseconds: set time_unit to \"ms\""),
            std::string::npos);
  // Seconds declared as microseconds: 5e-9 s periods (200 MHz).
  fmt.time_unit = TimeUnit::us;
  const std::string h =
      tmp.write("s.csv", "0.000,0,0,0,0,0,9.8\n0.005,0,0,0,0,0,9.8\n0.010,0,0,0,0,0,9.8\n");
  EXPECT_NE(CsvImuError(h, fmt).find("the timestamps look like seconds: set time_unit to \"s\""),
            std::string::npos);
}

TEST(ImuTiming, EurocFileInMicroseconds) {
  TempDir tmp;
  const std::string f =
      tmp.write("imu.csv", kShortEurocHeader + EurocRows(20, 1403715273262142, 5000));
  EXPECT_EQ(EurocImuError(f),
            f + ": the median period is 5e-06 s (rate 200000 Hz); the timestamps look like "
                "microseconds, but the EuRoC "
                "format reads nanoseconds: convert them, or read the file with \"format\": \"csv\" "
                "and \"time_unit\": \"us\" "
                "(an IMU rate is expected between 1 Hz and 100 kHz)");
}

TEST(ImuTiming, FindTimingIssueOnInlineTimes) {
  // For inline samples: the index of the sample after the gap, and the sentence.
  std::vector<double> t;
  for (int i = 0; i < 10; ++i) t.push_back(0.01 * i);
  t.push_back(1.0);
  const auto issue = FindTimingIssue(t, TimingPolicy{});
  ASSERT_TRUE(issue);
  EXPECT_EQ(issue->kind, TimingIssue::Kind::gap);
  EXPECT_EQ(issue->index, 10u);
  EXPECT_EQ(
      issue->message,
      "gap of 0.91 s before this sample (the median period is 0.01 s; limit 10 x median = 0.1 s); "
      "set \"allow_gaps\": true in the IMU source to integrate across it");
  EXPECT_FALSE(FindTimingIssue(t, TimingPolicy{10, true}));
  // Two samples: nothing to compare a period with, only the rate is judged.
  EXPECT_FALSE(FindTimingIssue({0.0, 0.5}, TimingPolicy{}));
  const auto slow = FindTimingIssue({0.0, 2.0, 4.0}, TimingPolicy{}, TimeUnit::s);
  ASSERT_TRUE(slow);
  EXPECT_EQ(slow->kind, TimingIssue::Kind::rate);
  // 2 s read as ms would be 500 Hz, as us 500 kHz (implausible): ms.
  EXPECT_NE(slow->message.find("the timestamps look like milliseconds: set time_unit to \"ms\""),
            std::string::npos)
      << slow->message;
  // No unit fits: stamps 1e10 apart give at most 0.1 Hz in any unit (the slowest reading is
  // in ns: 10 s).
  const auto none = FindTimingIssue({0.0, 1e10, 2e10}, TimingPolicy{}, TimeUnit::s);
  ASSERT_TRUE(none);
  EXPECT_NE(none->message.find("no time unit (s, ms, us, ns) gives a plausible rate"),
            std::string::npos)
      << none->message;
  // The lower median: with one gap among two periods the gap is judged by the short one.
  EXPECT_EQ(MedianPeriod({0.0, 0.01, 1.0}), 0.01);
}

// ---- ground truth holes ----------------------------------------------------------------------
TEST(GroundTruthTiming, HoleIsAnError) {
  TempDir tmp;
  // 20 Hz rows, 2 s missing before row 30 (line 32).
  const std::string f = tmp.write("gt.csv", GtRows(60, 1000000000, 50000000, 30, 1950000000));
  const TimeOrigin o{TimeValue{0, 0.0}, TimeUnit::ns};
  EXPECT_EQ(MessageOf<ReadError>([&] { ReadEurocGroundTruth(f, o); }),
            f + ":32: gap of 2 s before this row (the median period is 0.05 s; limit 10 x median = "
                "0.5 s); set "
                "\"allow_gaps\": true in the ground_truth object to interpolate across it");
  ReadOptions allow;
  allow.timing.allow_gaps = true;
  EXPECT_EQ(ReadEurocGroundTruth(f, o, allow).t.size(), 60u);
  // Stamps in milliseconds (20 Hz read as 20 MHz). As microseconds they would give 20 kHz,
  // also plausible; milliseconds are nearer the usual rates.
  const std::string g = tmp.write("gt_ms.csv", GtRows(10, 1000000, 50));
  EXPECT_EQ(MessageOf<ReadError>([&] { ReadEurocGroundTruth(g, o); }),
            g + ": the median period is 5e-08 s (rate 2e+07 Hz); the timestamps look like "
                "milliseconds, but ground-truth "
                "files are read in nanoseconds: convert them (a ground-truth rate is expected "
                "between 1 Hz and 100 kHz)");
}

// ---- 3. the kept range -----------------------------------------------------------------------
TEST(KeepRange, OnlyTheRangeAndOneSampleEachSideAreKept) {
  TempDir tmp;
  // 10 s at 200 Hz; t relative to the first stamp.
  const std::string f =
      tmp.write("imu.csv", kShortEurocHeader + EurocRows(2000, 1000000000, 5000000));
  ReadOptions o;
  o.keep = std::make_pair(2.0, 3.0);
  const ImuData d = ReadEurocImu(f, std::nullopt, o);
  // t = 2.000 ... 3.000 is 201 samples, plus 1.995 and 3.005.
  ASSERT_EQ(d.samples.size(), 203u);
  EXPECT_EQ(d.samples.front().t, 1.995);
  EXPECT_EQ(d.samples[1].t, 2.0);
  EXPECT_EQ(d.samples.back().t, 3.005);
  EXPECT_EQ(d.origin->nanoseconds().value(),
            1000000000);  // the file's first stamp, not the range's
  // Between two samples: just the two around it.
  o.keep = std::make_pair(2.0012, 2.0013);
  const ImuData two = ReadEurocImu(f, std::nullopt, o);
  ASSERT_EQ(two.samples.size(), 2u);
  EXPECT_EQ(two.samples[0].t, 2.0);
  EXPECT_EQ(two.samples[1].t, 2.005);
  // Before the start and after the end: the first / the last sample.
  o.keep = std::make_pair(-5.0, -1.0);
  ASSERT_EQ(ReadEurocImu(f, std::nullopt, o).samples.size(), 1u);
  o.keep = std::make_pair(100.0, 200.0);
  const ImuData late = ReadEurocImu(f, std::nullopt, o);
  ASSERT_EQ(late.samples.size(), 1u);
  EXPECT_EQ(late.samples[0].t, 9.995);
  // The generic CSV and the ground truth keep the same way.
  CsvFormat fmt;
  fmt.comment = "#";
  fmt.time_unit = TimeUnit::ns;
  o.keep = std::make_pair(2.0, 3.0);
  EXPECT_EQ(ReadCsvImu(f, fmt, o).samples.size(), 203u);
  const std::string g = tmp.write("gt.csv", GtRows(200, 1000000000, 50000000));
  const GroundTruth gt =
      ReadEurocGroundTruth(g, TimeOrigin{TimeValue{1000000000, 0.0}, TimeUnit::ns}, o);
  ASSERT_EQ(gt.t.size(), 23u);  // 2.00 ... 3.00 every 0.05 s, plus 1.95 and 3.05
  EXPECT_EQ(gt.t.front(), 1.95);
  EXPECT_EQ(gt.t.back(), 3.05);
  EXPECT_EQ(gt.x.size(), gt.t.size());
  EXPECT_EQ(gt.x[1].p.x(), 40.0);  // row 40 is t = 2.0
}

TEST(KeepRange, EveryLineIsStillValidated) {
  TempDir tmp;
  std::string body = kShortEurocHeader + EurocRows(2000, 1000000000, 5000000);
  body += "20000000000,0,0,nan,0,0,9.81\n";  // line 2002, far after the range
  const std::string f = tmp.write("imu.csv", body);
  ReadOptions o;
  o.keep = std::make_pair(2.0, 3.0);
  EXPECT_EQ(EurocImuError(f, o),
            f + ":2002: column 3 (w_z): expected a finite number, found 'nan'");
  const std::string g =
      tmp.write("back.csv", kShortEurocHeader + EurocRows(2000, 1000000000, 5000000) +
                                "1000000000,0,0,0,0,0,9.81\n");
  EXPECT_NE(EurocImuError(g, o).find(g + ":2002: timestamp 1000000000 is not after"),
            std::string::npos);
}

TEST(KeepRange, TimingIsJudgedOnTheKeptRange) {
  TempDir tmp;
  // A 1 s gap before row 1000 (t = 4.995 + 1 s): outside [1, 2] it does not matter.
  const std::string f = tmp.write(
      "imu.csv", kShortEurocHeader + EurocRows(2000, 1000000000, 5000000, 1000, 1000000000));
  ReadOptions o;
  o.keep = std::make_pair(1.0, 2.0);
  EXPECT_EQ(ReadEurocImu(f, std::nullopt, o).samples.size(), 203u);
  o.keep = std::make_pair(5.5, 6.5);
  EXPECT_EQ(EurocImuError(f, o),
            f + ":1002: gap of 1.005 s before this sample (the median period is 0.005 s; limit 10 "
                "x median = 0.05 s); "
                "set \"allow_gaps\": true in the IMU source to integrate across it");
  // A range inside the gap keeps the two samples around it; the median comes from the
  // neighbouring samples, so the gap is still seen.
  o.keep = std::make_pair(5.2, 5.3);
  EXPECT_NE(EurocImuError(f, o).find(f + ":1002: gap of 1.005 s"), std::string::npos);
}

// ---- 4./5. regular files only: a FIFO must not block, a device is refused ---------------------
// Runs `f` in a child process (a regression would block forever: the parent kills it after
// 20 s) and returns the message the child wrote, or a description of what went wrong.
std::string MessageInChild(const std::function<std::string()>& f) {
  int fds[2];
  if (::pipe(fds) != 0) return "pipe failed";
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::close(fds[0]);
    const std::string m = f();
    [[maybe_unused]] const auto w = ::write(fds[1], m.data(), m.size());
    ::_exit(0);
  }
  ::close(fds[1]);
  int status = 0;
  bool done = false;
  for (int i = 0; i < 2000 && !done; ++i) {  // 2000 x 10 ms = 20 s
    done = ::waitpid(pid, &status, WNOHANG) == pid;
    if (!done) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  if (!done) {
    ::kill(pid, SIGKILL);
    ::waitpid(pid, &status, 0);
    ::close(fds[0]);
    return "timed out: the reader blocked";
  }
  std::string out;
  char buf[4096];
  ssize_t n;
  while ((n = ::read(fds[0], buf, sizeof buf)) > 0) out.append(buf, static_cast<std::size_t>(n));
  ::close(fds[0]);
  return out;
}

TEST(RegularFilesOnly, FifoIsRefusedWithoutBlocking) {
  TempDir tmp;
  const std::string fifo = tmp.file("input.fifo");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const std::string expect = fifo + ": is a FIFO, not a regular file";
  EXPECT_EQ(MessageInChild([&] { return EurocImuError(fifo); }), expect);
  EXPECT_EQ(MessageInChild([&] { return CsvImuError(fifo, CsvFormat{}); }), expect);
  EXPECT_EQ(MessageInChild([&] {
              return MessageOf<ReadError>([&] { ReadEurocGroundTruth(fifo, TimeOrigin{}); });
            }),
            expect);
  EXPECT_EQ(
      MessageInChild([&] { return MessageOf<ReadError>([&] { (void)ParseJsonFile(fifo); }); }),
      expect);
  // A symlink to the FIFO is the FIFO.
  const std::string link = tmp.file("link.json");
  ASSERT_EQ(::symlink(fifo.c_str(), link.c_str()), 0);
  EXPECT_EQ(
      MessageInChild([&] { return MessageOf<ReadError>([&] { (void)ParseJsonFile(link); }); }),
      link + ": is a FIFO, not a regular file");
}

TEST(RegularFilesOnly, DevicesAndDirectories) {
  EXPECT_EQ(EurocImuError("/dev/null"), "/dev/null: is a character device, not a regular file");
  EXPECT_EQ(MessageOf<ReadError>([] { (void)ParseJsonFile("/dev/zero"); }),
            "/dev/zero: is a character device, not a regular file");
  TempDir tmp;
  EXPECT_EQ(MessageOf<ReadError>([&] { (void)ParseJsonFile(tmp.path()); }),
            tmp.path() + ": is a directory, not a file");
}

// ---- 4. JSON documents -----------------------------------------------------------------------
TEST(JsonDocument, DuplicateKeysAtTheirPointer) {
  TempDir tmp;
  const std::string f = tmp.write("p.json",
                                  "{\"a\": {\"b\": [1, {\"x\": 1, \"y\": [], \"x\": 2}], \"c/~d\": "
                                  "0, \"c/~d\": 1}, \"a2\": 0}");
  try {
    (void)ParseJsonFile(f);  // expected to throw
    FAIL() << "duplicate keys accepted";
  } catch (const ConfigError& e) {
    ASSERT_EQ(e.issues().size(), 2u) << e.what();
    EXPECT_EQ(e.issues()[0].pointer, "/a/b/1/x");
    EXPECT_EQ(e.issues()[1].pointer, "/a/c~1~0d");
    EXPECT_EQ(std::string(e.what()),
              f + ": /a/b/1/x: duplicate key 'x' (the last one would silently win)\n" + f +
                  ": /a/c~1~0d: duplicate key 'c/~d' (the last one would silently win)");
  }
  // The top level too.
  const std::string g = tmp.write("q.json", "{\"imu\": 1,\n \"imu\": 2}");
  EXPECT_EQ(MessageOf<ConfigError>([&] { (void)ParseJsonFile(g); }),
            g + ": /imu: duplicate key 'imu' (the last one would silently win)");
}

TEST(JsonDocument, BuildsTheSameDocumentAsNlohmann) {
  // The SAX builder must produce what json::parse does, for every example pipeline and a
  // measurement file.
  for (const char* rel :
       {"examples/euroc_v1_01_keyframes.json", "examples/generic_csv.json",
        "examples/gtsam_import.json", "examples/hover.state.json", "examples/inline_basics.json",
        "examples/data/gtsam_smooth0_manifold.measurements.json"}) {
    const std::string path = SourcePath(rel);
    EXPECT_EQ(ParseJsonFile(path), json::parse(imuconv::test::ReadText(path))) << rel;
  }
  TempDir tmp;
  const std::string f = tmp.write(
      "v.json",
      "[null, true, -3, 18446744073709551615, 1.5e-300, \"\\u00e9\", {}, [[]], {\"\": {\"\": 0}}]");
  EXPECT_EQ(ParseJsonFile(f), json::parse(imuconv::test::ReadText(f)));
}

TEST(JsonDocument, SyntaxErrorsSayLineAndColumnWithoutLibraryInternals) {
  TempDir tmp;
  const std::string f = tmp.write("a.json", "{\n  \"a\": tru }");
  std::string msg = MessageOf<ConfigError>([&] { (void)ParseJsonFile(f); });
  EXPECT_EQ(msg.rfind(f + ": (document): not valid JSON: parse error at line 2, column 11: syntax "
                          "error while parsing value",
                      0),
            0u)
      << msg;
  EXPECT_EQ(msg.find("json.exception"), std::string::npos) << msg;
  // Number overflow is an out_of_range (406) inside nlohmann: same form, no id.
  const std::string g = tmp.write("b.json", "{\"a\": [1,\n 1e400]}");
  msg = MessageOf<ConfigError>([&] { (void)ParseJsonFile(g); });
  EXPECT_EQ(msg, g + ": (document): not valid JSON: parse error at line 2, column 6: number "
                     "overflow parsing '1e400'")
      << msg;
  // Raw control bytes never reach the message.
  const std::string h = tmp.write("c.json", std::string("{\"a\": \"x\x1b[31m\n\"}"));
  msg = MessageOf<ConfigError>([&] { (void)ParseJsonFile(h); });
  EXPECT_EQ(msg.find('\x1b'), std::string::npos) << msg;
  EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
  EXPECT_EQ(msg.rfind(h + ": (document): not valid JSON: parse error at line 1, column 9: ", 0), 0u)
      << msg;
  // An empty file.
  const std::string e = tmp.write("e.json", "");
  msg = MessageOf<ConfigError>([&] { (void)ParseJsonFile(e); });
  EXPECT_EQ(msg.rfind(e + ": (document): not valid JSON: parse error at line 1, column 1: ", 0), 0u)
      << msg;
}

TEST(JsonDocument, LineAndColumnAreCountedAsNlohmannCountsThem) {
  // Our count comes from the byte offset; it must agree with the library's own.
  TempDir tmp;
  for (const std::string text : {"{\"a\": x}", "{\n\n  \"a\": [1, 2,, 3]}", "[1,\r\n2\r\n",
                                 "{\"a\": \"\n\"}", "\n\n\n", "[\"\xff\"]", "{\"a\" 1}", "[1] [2]",
                                 "", "[1,\n", "\xef\xbb\xbf{\"a\": x}", "\xef\xbb\xbf\n[,]"}) {
    const std::string f = tmp.write("x.json", text);
    std::string theirs;
    try {
      [[maybe_unused]] const json j = json::parse(text);
    } catch (const json::parse_error& e) {
      theirs = e.what();
    }
    const auto at = theirs.find("line ");
    ASSERT_NE(at, std::string::npos) << theirs;
    const std::string where = theirs.substr(at, theirs.find(':', at) - at);  // "line L, column C"
    const std::string ours = MessageOf<ConfigError>([&] { (void)ParseJsonFile(f); });
    EXPECT_NE(ours.find("parse error at " + where + ": "), std::string::npos)
        << ours << "\nvs " << theirs;
  }
}

TEST(JsonDocument, DeepNestingIsRefused) {
  TempDir tmp;
  const std::string f = tmp.write("deep.json", std::string(100000, '[') + std::string(100000, ']'));
  const std::string msg = MessageOf<ConfigError>([&] { (void)ParseJsonFile(f); });
  std::string ptr;
  for (std::size_t i = 0; i < kMaxJsonDepth; ++i) ptr += "/0";
  // The pointer is 512 bytes: shown up to 200.
  EXPECT_EQ(msg, f + ": " + ptr.substr(0, 200) +
                     "...: arrays and objects are nested deeper than 256 levels");
  // 256 levels are fine.
  const std::string g = tmp.write("ok.json", std::string(256, '[') + std::string(256, ']'));
  EXPECT_NO_THROW((void)ParseJsonFile(g));
}

TEST(JsonDocument, SizeLimit) {
  // A sparse file one byte over the limit: refused from its size, before anything is read.
  TempDir tmp;
  const std::string f = tmp.file("big.json");
  const int fd = ::open(f.c_str(), O_CREAT | O_WRONLY, 0600);
  ASSERT_GE(fd, 0);
  ASSERT_EQ(::ftruncate(fd, static_cast<off_t>(kMaxJsonBytes + 1)), 0);
  ::close(fd);
  EXPECT_EQ(MessageOf<ReadError>([&] { (void)ParseJsonFile(f); }),
            f + ": is larger than 256 MiB, the largest JSON document imuconv reads");
}

TEST(JsonDocument, MemoryEstimateStopsManyTinyValues) {
  // 20 000 empty arrays: 60 kB of text, about 1.6 MB once parsed (estimated 80 B each).
  TempDir tmp;
  std::string doc = "[[]";
  for (int i = 1; i < 20000; ++i) doc += ",[]";
  const std::string f = tmp.write("tiny.json", doc + "]");
  JsonLimits limits;
  limits.max_memory = std::size_t{1} << 20;
  EXPECT_EQ(MessageOf<ReadError>([&] { (void)ParseJsonFile(f, limits); }),
            f + ": would take more than 1 MiB of memory once parsed: it holds too many small "
                "values (imuconv's own "
                "documents take about twice their size)");
  limits.max_memory = std::size_t{4} << 20;
  EXPECT_EQ(ParseJsonFile(f, limits).size(), 20000u);
  // A real document under the same 1 MiB bound (its text is 2 kB).
  limits.max_memory = std::size_t{1} << 20;
  EXPECT_NO_THROW((void)ParseJsonFile(SourcePath("examples/euroc_v1_01_keyframes.json"), limits));
}

// ---- 6. error output is capped -----------------------------------------------------------------
TEST(ErrorCap, TwoHundredThousandUnknownKeysGiveAShortMessage) {
  TempDir tmp;
  std::string doc = "{\"a\": 1";
  for (int i = 0; i < 200000; ++i) doc += ",\"k" + std::to_string(i) + "\": 0";
  doc += "}";
  const std::string f = tmp.write("keys.json", doc);
  const json j = ParseJsonFile(f);
  Checker c(f);
  Node(j, "", c).expect_object({"a"});
  EXPECT_EQ(c.count(), 200000u);
  EXPECT_EQ(c.issues().size(), Checker::kMaxStored);
  try {
    c.throw_if_errors();
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    const std::string msg = e.what();
    EXPECT_EQ(std::count(msg.begin(), msg.end(), '\n'), 20) << msg.substr(0, 2000);
    EXPECT_EQ(e.issues().size(), Checker::kMaxStored);
    EXPECT_EQ(e.total(), 200000u);
    // Keys sort as strings: k0, k1, k10, k100, ...
    EXPECT_EQ(msg.rfind(f + ": /k0: unknown key 'k0' (allowed here: 'a')\n", 0), 0u)
        << msg.substr(0, 200);
    const std::string tail = "\n... and 199980 more problems in " + f;
    EXPECT_EQ(msg.substr(msg.size() - tail.size()), tail);
  }
  // 20 problems exactly: no tail line.
  Checker few(f);
  for (int i = 0; i < 20; ++i) few.error("/x", "bad");
  EXPECT_EQ(MessageOf<ConfigError>([&] { few.throw_if_errors(); }).find("more problems"),
            std::string::npos);
}

// ---- 7. untrusted text is escaped
// ----------------------------------------------------------------
TEST(Escaping, FileNamesKeysAndFieldsInMessages) {
  TempDir tmp;
  const std::string f = tmp.file("a\nok b.csv");
  EXPECT_EQ(EurocImuError(f), tmp.path() + "/a\\nok b.csv: cannot open the file for reading");
  // A header name with an escape sequence, and a field with a control byte.
  const std::string g = tmp.write("h.csv", "t,g\x1b[2Jx,gy,gz,ax,ay,az\n0,0,0,0,0,0,9.8\n");
  CsvFormat fmt;
  fmt.header_rows = 1;
  fmt.columns = {std::string("t"), std::string("gx"), 2, 3, 4, 5, 6};
  EXPECT_EQ(CsvImuError(g, fmt),
            g + ":1: no column named 'gx' (for 'wx') in the header; columns: 't', 'g\\x1b[2Jx', "
                "'gy', 'gz', 'ax', 'ay', 'az'");
  const std::string h = tmp.write("f.csv", kShortEurocHeader +
                                               "1000,0,0,\x07"
                                               "1,0,0,9.81\n");
  EXPECT_EQ(EurocImuError(h), h + ":2: column 3 (w_z): expected a finite number, found '\\x071'");
  // A JSON key with a newline, in the pointer and in the message.
  const std::string j = tmp.write("k.json", "{\"a\\nb\": 1, \"a\\nb\": 2}");
  EXPECT_EQ(MessageOf<ConfigError>([&] { (void)ParseJsonFile(j); }),
            j + ": /a\\nb: duplicate key 'a\\nb' (the last one would silently win)");
  // A megabyte key is cut in the message (and in the pointer shown).
  const std::string big(1 << 20, 'k');
  const std::string k = tmp.write("big.json", "{\"" + big + "\": 1, \"" + big + "\": 2}");
  EXPECT_EQ(MessageOf<ConfigError>([&] { (void)ParseJsonFile(k); }),
            k + ": /" + big.substr(0, 199) + "...: duplicate key '" + big.substr(0, 80) +
                "...' (the last one would silently win)");
}

}  // namespace
