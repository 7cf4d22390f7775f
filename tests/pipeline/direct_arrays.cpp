// RunToArrays (imuconv run -o OUT.npz) collects the arrays from the values the tasks write,
// not from the JSON text read back: it must give what the text gives, name for name, shape
// for shape and bit for bit, sidecar byte for byte, for every example pipeline, and the writer's
// value events must carry every kind of value the text can (escaped strings, integers beyond
// int64, -0.0, nulls, long rows) and fail where the text fails, with the same message.
//
// No tolerance anywhere: the arrays are compared as 64-bit patterns, the sidecar and the
// archives as bytes.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <random>

#include "../../apps/pipeline/src/io/number_format.h"
#include "../../apps/pipeline/src/io/result_collector.h"
#include "imuconv/pipeline/json_writer.h"
#include "imuconv/pipeline/pipeline.h"
#include "imuconv/pipeline/result_arrays.h"
#include "imuconv/printable.h"
#include "imuconv_test.h"
#include "pipeline_test_util.h"

namespace imuconv::test {
namespace {

using pipeline::JsonWriter;
using pipeline::NdArray;
using pipeline::ResultArrays;

void ExpectSameArrays(const ResultArrays& a, const ResultArrays& b, const std::string& what) {
  ASSERT_EQ(a.arrays.size(), b.arrays.size()) << what;
  for (std::size_t i = 0; i < a.arrays.size(); ++i) {
    const auto& [name_a, x] = a.arrays[i];
    const auto& [name_b, y] = b.arrays[i];
    ASSERT_EQ(name_a, name_b) << what << ": array " << i;
    EXPECT_EQ(x.type, y.type) << what << ": " << name_a;
    EXPECT_EQ(x.shape, y.shape) << what << ": " << name_a;
    ASSERT_EQ(x.data.size(), y.data.size()) << what << ": " << name_a;
    ASSERT_EQ(x.integers.size(), y.integers.size()) << what << ": " << name_a;
    // The bits, so that -0.0 and 0.0 differ.
    EXPECT_EQ(0, x.data.empty() ? 0 : std::memcmp(x.data.data(), y.data.data(), 8 * x.data.size()))
        << what << ": " << name_a;
    EXPECT_EQ(x.integers, y.integers) << what << ": " << name_a;
  }
  EXPECT_EQ(a.sidecar, b.sidecar) << what;
}

std::string Npz(const ResultArrays& r) {
  std::string bytes;
  pipeline::WriteResultNpz(r, [&](std::string_view s) { bytes.append(s.data(), s.size()); });
  return bytes;
}

TEST(DirectArrays, EveryExampleGivesWhatItsTextGives) {
  std::size_t examples = 0;
  for (const auto& entry : std::filesystem::directory_iterator(SourcePath("examples"))) {
    if (entry.path().extension() != ".json" ||
        entry.path().filename().string().find(".state.") != std::string::npos)
      continue;
    const pipeline::Pipeline p = pipeline::Pipeline::Load(entry.path().string());
    for (unsigned threads : {1u, 2u}) {
      pipeline::RunOptions o;
      o.threads = threads;
      std::string text;
      pipeline::RunToText(p, Plugins(), o,
                          [&](std::string_view s) { text.append(s.data(), s.size()); });
      const ResultArrays from_text =
          pipeline::CollectResultArrays(text, "the output of " + Printable(p.file()));
      bool started = false;
      const ResultArrays direct = pipeline::RunToArrays(p, Plugins(), o, [&] {
        EXPECT_FALSE(started) << "started is called once";
        started = true;
      });
      EXPECT_TRUE(started);
      const std::string what =
          entry.path().filename().string() + " with " + std::to_string(threads) + " thread(s)";
      ExpectSameArrays(direct, from_text, what);
      EXPECT_EQ(Npz(direct), Npz(from_text)) << what;
    }
    ++examples;
  }
  EXPECT_GE(examples, 6u);  // the examples/ pipelines (7 when this was written, one a state file)
}

TEST(DirectArrays, CheckOnlyRunsNothing) {
  const pipeline::Pipeline p = pipeline::Pipeline::Load(SourcePath("examples/inline_basics.json"));
  pipeline::RunOptions o;
  o.check_only = true;
  bool started = false;
  const ResultArrays r = pipeline::RunToArrays(p, Plugins(), o, [&] { started = true; });
  EXPECT_FALSE(started);
  EXPECT_TRUE(r.arrays.empty());
}

/// A document with every kind of value, written by `w` (either form).
void WriteEveryKind(JsonWriter& w) {
  w.begin_object();
  w.key("format");
  w.string("quote \" backslash \\ tab \t newline \n bell \x07 utf-8 \xc3\xa9");
  w.key("ints");
  w.begin_line_array();
  w.integer(-5);
  w.integer(std::numeric_limits<std::int64_t>::min());
  w.unsigned_integer(7);
  w.end_array();
  w.key("big");
  w.unsigned_integer(std::numeric_limits<std::uint64_t>::max());  // beyond int64: a sidecar value
  w.key("zeros");
  const double zeros[] = {0.0, -0.0, 5e-324, -1.7976931348623157e308};
  w.numbers(zeros, 4);
  std::vector<double> row(40);  // longer than one formatting buffer
  for (std::size_t i = 0; i < row.size(); ++i) row[i] = 0.1 * static_cast<double>(i) - 1.0 / 3.0;
  w.key("long_row");
  w.numbers(row.data(), row.size());
  w.key("nan_as_null");
  const double with_nan[] = {1.0, std::nan(""), 2.5};
  w.numbers(with_nan, 3);
  w.key("flags");
  w.begin_line_array();
  w.boolean(true);
  w.boolean(false);
  w.null();
  w.end_array();
  w.key("empty");
  w.begin_object();
  w.end_object();
  // Matrices, which the events carry whole with their shape: of every edge shape, and one with
  // a NaN (written row by row, as null in the text).
  w.key("no_rows");
  w.matrix(Eigen::MatrixXd(0, 3));
  w.key("empty_rows");
  w.matrix(Eigen::MatrixXd(2, 0));
  w.key("one_by_one");
  w.matrix(Eigen::Matrix<double, 1, 1>::Constant(-0.25));
  Eigen::MatrixXd wide(3, 40);  // rows longer than one formatting buffer
  for (Eigen::Index i = 0; i < wide.size(); ++i) wide(i) = 1.0 / (1.0 + static_cast<double>(i));
  w.key("wide");
  w.matrix(wide);
  Eigen::Matrix2d with_nan_m = Eigen::Matrix2d::Identity();
  with_nan_m(1, 0) = std::nan("");
  w.key("matrix_with_nan");
  w.matrix(with_nan_m);
  w.key("empty_vector");
  w.vector(Eigen::VectorXd(0));
  w.key("long_vector");
  w.vector(wide.row(1).transpose());
  w.key("tasks");
  w.begin_array();
  for (int t = 0; t < 2; ++t) {
    w.begin_object();
    w.key("name");
    w.string(t == 0 ? "a/b~c" : "second");
    w.key("steps");
    w.begin_array();
    for (int k = 0; k < 3; ++k) {
      w.begin_object();
      w.key("k");
      w.integer(k);
      w.key("m");
      w.matrix(Eigen::Matrix2d::Constant(1.5 * k + t));
      w.end_object();
    }
    w.end_array();
    w.key("labels");
    w.value(nlohmann::json::array({"R", "p", 3, 2.0, nullptr}));
    w.end_object();
  }
  w.end_array();
  w.end_object();
}

TEST(DirectArrays, EventsCarryEveryKindOfValueAsTheTextDoes) {
  std::string text, events;
  JsonWriter tw(text, 0, {}, JsonWriter::NonFinite::Null);
  WriteEveryKind(tw);
  JsonWriter ew(events, 0, {}, JsonWriter::NonFinite::Null, JsonWriter::Form::kEvents);
  WriteEveryKind(ew);
  const ResultArrays from_text = pipeline::CollectResultArrays(text, "doc");
  pipeline::detail::EventCollector whole("doc");
  whole.feed(events);
  ExpectSameArrays(whole.finish(), from_text, "events in one piece");
  // Pieces that cut records anywhere (the output hands whole records over, but the collector
  // must not depend on it).
  pipeline::detail::EventCollector bytes("doc");
  for (char c : events) bytes.feed(std::string_view(&c, 1));
  ExpectSameArrays(bytes.finish(), from_text, "events byte by byte");
}

// A matrix's events are its shape and its numbers, one record: the collector takes the shape as
// written instead of reading it off nested arrays.
TEST(DirectArrays, AMatrixIsOneRecordWithItsShape) {
  std::string events;
  JsonWriter w(events, 0, {}, JsonWriter::NonFinite::Throw, JsonWriter::Form::kEvents);
  Eigen::Matrix<double, 15, 15> m;
  for (Eigen::Index i = 0; i < m.size(); ++i) m(i) = static_cast<double>(i);
  w.matrix(m);
  ASSERT_EQ(events.size(), 1u + 8 + 8 + 8 * 225);
  EXPECT_EQ(events[0], 'm');
  std::uint64_t rows = 0, cols = 0;
  double m01 = 0;
  std::memcpy(&rows, events.data() + 1, 8);
  std::memcpy(&cols, events.data() + 9, 8);
  std::memcpy(&m01, events.data() + 17 + 8, 8);  // row-major: the second number is (0, 1)
  EXPECT_EQ(rows, 15u);
  EXPECT_EQ(cols, 15u);
  EXPECT_EQ(m01, m(0, 1));
}

TEST(DirectArrays, NonFiniteFailsWithTheTextsMessage) {
  for (int where = 0; where < 3; ++where) {
    std::string messages[2];
    for (int form = 0; form < 2; ++form) {
      std::string out;
      JsonWriter w(out, 0, {}, JsonWriter::NonFinite::Throw,
                   form == 0 ? JsonWriter::Form::kText : JsonWriter::Form::kEvents);
      w.begin_object();
      w.key("x");
      try {
        const double inf = std::numeric_limits<double>::infinity();
        if (where == 0) {
          w.number(inf);
        } else {
          std::vector<double> v(where == 1 ? 5 : 40, 1.0);
          v[3] = -inf;
          w.numbers(v.data(), v.size());
        }
      } catch (const Error& e) {
        messages[form] = e.what();
      }
    }
    EXPECT_FALSE(messages[0].empty());
    EXPECT_EQ(messages[1], messages[0]);
  }
}

TEST(DirectArrays, IncompleteEventsAreRefused) {
  std::string events;
  JsonWriter w(events, 0, {}, JsonWriter::NonFinite::Throw, JsonWriter::Form::kEvents);
  w.begin_object();
  w.key("x");
  w.number(1.0);
  pipeline::detail::EventCollector c("doc");
  c.feed(events.substr(0, events.size() - 3));  // a number cut short, and no closing brace
  EXPECT_THROW(c.finish(), std::exception);
}

// The writer remembers the texts of recent numbers (a small table per thread, by their bits):
// a number written again, or one that takes another's slot, must still read as FormatShortest
// writes it. 600 distinct doubles of every magnitude (and both zeros) drawn 20000 times fill
// the 512 slots many times over, with repeats and collisions.
TEST(DirectArrays, RepeatedNumbersAreWrittenAsTheFirstTime) {
  std::mt19937_64 rng(7);
  std::vector<double> pool{0.0, -0.0, 1.0, -1.0, 0.1, 1e-5, 1e16};
  while (pool.size() < 600) {
    const std::uint64_t bits = rng();
    double v;
    std::memcpy(&v, &bits, sizeof v);
    if (std::isfinite(v)) pool.push_back(v);
  }
  std::string text, expected = "[";
  JsonWriter w(text);
  w.begin_line_array();
  for (int i = 0; i < 20000; ++i) {
    const double v = pool[rng() % pool.size()];
    if (i % 3 == 0)
      w.number(v);
    else
      w.numbers(&v, 1);  // the row path: "[v]"
    char buf[pipeline::kMaxDoubleChars + 1];
    const std::string one(buf, pipeline::FormatShortest(buf, v));
    expected += (i ? ", " : "") + (i % 3 == 0 ? one : "[" + one + "]");
  }
  w.end_array();
  EXPECT_EQ(text, expected + "]");
}

}  // namespace
}  // namespace imuconv::test
