// The residual task's sink (apps/pipeline/src/tasks/residual_json_sink.h): what a residual
// plugin writes reaches the JSON under its names, vectors on one line and matrices as rows,
// and a hostile plugin's slips (a null or repeated name, a non-finite number, a size out of
// bounds, an unbalanced group, a second or negative distance) become one message that names
// what went wrong, instead of a crash, a broken document or a silent wrong answer.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <string>

#include "../../apps/pipeline/src/tasks/residual_json_sink.h"
#include "imuconv/pipeline/json_writer.h"

namespace {
using imuconv::pipeline::JsonWriter;
using imuconv::pipeline::ResidualJsonSink;

/// Runs `write` on a sink inside an open object; returns the text and the sink's problem.
template <class Write>
std::pair<std::string, std::string> SinkWritten(const Write& write) {
  std::string text;
  JsonWriter w(text);
  w.begin_object();
  ResidualJsonSink sink(w);
  write(sink);
  std::string problem = sink.problem();
  if (problem.empty()) w.end_object();
  return {text, problem};
}

TEST(ResidualJsonSink, WritesVectorsOnOneLineMatricesAsRowsAndGroups) {
  const double v[3] = {1.0, -2.5, 3.0};
  const double m[6] = {1, 2, 3, 4, 5, 6};  // 2 x 3, row-major
  const auto [text, problem] = SinkWritten([&](ResidualJsonSink& s) {
    s.begin_group("raw");
    s.vector("residual", v, 3);
    s.end_group();
    s.matrix("J", m, 2, 3);
    s.mahalanobis_squared(4.0);
  });
  EXPECT_EQ(problem, "");
  EXPECT_EQ(text,
            "{\n  \"raw\": {\n    \"residual\": [1.0, -2.5, 3.0]\n  },\n  \"J\": [\n    [1.0, 2.0, "
            "3.0],\n    [4.0, 5.0, 6.0]\n  ]\n}");
}

TEST(ResidualJsonSink, KeepsTheDistanceOnlyWhenFiniteAndGivenOnce) {
  std::string text;
  JsonWriter w(text);
  w.begin_object();
  ResidualJsonSink ok(w);
  ok.mahalanobis_squared(2.0);
  ASSERT_TRUE(ok.distance());
  EXPECT_EQ(*ok.distance(), 2.0);
  ok.mahalanobis_squared(3.0);
  EXPECT_NE(ok.problem().find("twice"), std::string::npos) << ok.problem();
  for (double bad : {-1.0, std::nan(""), std::numeric_limits<double>::infinity()}) {
    ResidualJsonSink s(w);
    s.mahalanobis_squared(bad);
    EXPECT_NE(s.problem().find("expected a finite number >= 0"), std::string::npos);
  }
}

TEST(ResidualJsonSink, RefusesWhatAHostilePluginMightWrite) {
  const double v[2] = {1.0, std::nan("")};
  const double ok[2] = {1.0, 2.0};
  struct SinkCase {
    const char* what;
    std::function<void(ResidualJsonSink&)> write;
    const char* expect;
  };
  const SinkCase cases[] = {
      {"null name", [&](ResidualJsonSink& s) { s.vector(nullptr, ok, 2); }, "null name"},
      {"empty name", [&](ResidualJsonSink& s) { s.vector("", ok, 2); }, "1 to 64 bytes"},
      {"not UTF-8", [&](ResidualJsonSink& s) { s.vector("r\xff", ok, 2); }, "1 to 64 bytes"},
      {"twice", [&](ResidualJsonSink& s) { s.vector("r", ok, 2), s.vector("r", ok, 2); },
       "wrote 'r' twice"},
      {"non-finite", [&](ResidualJsonSink& s) { s.vector("r", v, 2); }, "non-finite number"},
      {"null array", [&](ResidualJsonSink& s) { s.matrix("J", nullptr, 1, 2); }, "null array"},
      {"zero size", [&](ResidualJsonSink& s) { s.vector("r", ok, 0); }, "size of 0 x 1"},
      {"negative size", [&](ResidualJsonSink& s) { s.matrix("J", ok, -1, 2); }, "size of -1 x 2"},
      {"too many numbers", [&](ResidualJsonSink& s) { s.matrix("J", ok, 1 << 16, 1 << 16); },
       "at most 1048576 numbers"},
      {"close unopened", [&](ResidualJsonSink& s) { s.end_group(); }, "had not opened"},
      {"left open", [&](ResidualJsonSink& s) { s.begin_group("g"); }, "left a group open"},
  };
  for (const SinkCase& c : cases) {
    const auto [text, problem] = SinkWritten(c.write);
    EXPECT_NE(problem.find(c.expect), std::string::npos) << c.what << ": " << problem;
  }
  // The first problem is kept; what follows is ignored.
  const auto [text, problem] = SinkWritten([&](ResidualJsonSink& s) {
    s.vector(nullptr, ok, 2);
    s.end_group();
  });
  EXPECT_NE(problem.find("null name"), std::string::npos) << problem;
}

}  // namespace
