// Independent intervals run on a thread pool; the output must not depend on it: a parallel
// run's document is byte-identical to a serial run's (library and command line), and a
// failing run reports the same error whatever the thread count. Also: the whole-file EuRoC
// example (examples/euroc_v1_01_full.json, 1447 keyframe intervals over 144.7 s).
#include <gtest/gtest.h>

#include <atomic>
#include <set>
#include <stdexcept>

#include "../../apps/pipeline/src/io/thread_pool.h"
#include "imuconv/pipeline/json_io.h"
#include "imuconv/pipeline/pipeline.h"
#include "imuconv_test.h"
#include "pipeline_test_util.h"

namespace {
using namespace imuconv;
using namespace imuconv::pipeline;
using imuconv::test::SourcePath;
using nlohmann::json;

std::string RunText(const Pipeline& p, unsigned threads, std::string* summary = nullptr) {
  std::string text;
  std::ostringstream s;
  RunOptions o;
  o.threads = threads;
  o.summary = &s;
  RunToText(p, imuconv::test::Plugins(), o,
            [&](std::string_view piece) { text.append(piece.data(), piece.size()); });
  if (summary) *summary = s.str();
  return text;
}

TEST(ThreadPool, EveryItemOnceAndTheLowestFailureWins) {
  for (unsigned threads : {1u, 2u, 5u}) {
    SCOPED_TRACE(threads);
    ThreadPool pool(threads);
    EXPECT_EQ(pool.size(), threads);
    // A window as large as n: items are produced as freely as the pool allows.
    std::vector<std::atomic<int>> hits(1000);
    pool.ordered_for(
        hits.size(), hits.size(), [&](std::size_t i) { hits[i]++; }, [](std::size_t) {});
    for (const auto& h : hits) ASSERT_EQ(h.load(), 1);
    // Items 700, 300 and 301 throw: the error of 300 is reported (as a serial loop would).
    try {
      pool.ordered_for(
          1000, 1000,
          [&](std::size_t i) {
            if (i == 700 || i == 300 || i == 301)
              throw std::runtime_error("item " + std::to_string(i));
          },
          [](std::size_t) {});
      FAIL() << "no exception";
    } catch (const std::runtime_error& e) {
      EXPECT_STREQ(e.what(), "item 300");
    }
    // The pool is usable after a failure.
    std::atomic<std::size_t> sum{0};
    pool.ordered_for(
        100, 100, [&](std::size_t i) { sum += i; }, [](std::size_t) {});
    EXPECT_EQ(sum.load(), 4950u);
  }
  ThreadPool every_core(0);
  EXPECT_GE(every_core.size(), 1u);
}

TEST(ThreadPool, OrderedForConsumesInOrderWithinTheWindow) {
  for (unsigned threads : {1u, 2u, 5u}) {
    SCOPED_TRACE(threads);
    ThreadPool pool(threads);
    constexpr std::size_t n = 2000, window = 7;
    std::vector<std::atomic<int>> produced(n);
    std::atomic<std::size_t> consumed{0};
    std::atomic<bool> ahead{false};
    std::vector<std::size_t> order;
    pool.ordered_for(
        n, window,
        [&](std::size_t i) {
          if (i >= consumed.load() + window)
            ahead = true;  // started before i - window was consumed
          produced[i]++;
        },
        [&](std::size_t i) {
          EXPECT_EQ(produced[i].load(), 1);
          order.push_back(i);
          consumed = i + 1;
        });
    EXPECT_FALSE(ahead.load());
    ASSERT_EQ(order.size(), n);
    for (std::size_t i = 0; i < n; ++i) ASSERT_EQ(order[i], i);
    for (const auto& p : produced) ASSERT_EQ(p.load(), 1);
    // The lowest failing item wins; nothing after it is consumed.
    std::size_t last = 0;
    const std::string msg = imuconv::test::MessageOf<std::runtime_error>([&] {
      pool.ordered_for(
          n, window,
          [&](std::size_t i) {
            if (i == 1500 || i == 900 || i == 901)
              throw std::runtime_error("item " + std::to_string(i));
          },
          [&](std::size_t i) { last = i; });
    });
    EXPECT_EQ(msg, "item 900");
    EXPECT_EQ(last, 899u);
    // A failing consumer stops the loop at once.
    const std::string m2 = imuconv::test::MessageOf<std::runtime_error>([&] {
      pool.ordered_for(
          n, window, [](std::size_t) {},
          [](std::size_t i) {
            if (i == 10) throw std::runtime_error("sink");
          });
    });
    EXPECT_EQ(m2, "sink");
  }
}

TEST(Parallel, EveryExampleIsByteIdenticalToASerialRun) {
  for (const char* name : {"euroc_v1_01_keyframes.json", "inline_basics.json", "generic_csv.json",
                           "gtsam_import.json"}) {
    SCOPED_TRACE(name);
    const Pipeline p = Pipeline::Load(SourcePath(std::string("examples/") + name));
    std::string serial_summary, parallel_summary;
    const std::string serial = RunText(p, 1, &serial_summary);
    ASSERT_GT(serial.size(), 100u);
    for (unsigned threads : {2u, 3u, 8u}) {
      // Compared as strings so that a failure does not print megabytes.
      const std::string parallel = RunText(p, threads, &parallel_summary);
      EXPECT_TRUE(parallel == serial)
          << threads << " threads: " << parallel.size() << " bytes vs " << serial.size();
      EXPECT_EQ(parallel_summary, serial_summary);
    }
    // Run() is the same document, parsed.
    RunOptions o;
    o.threads = 3;
    EXPECT_EQ(pipeline::Run(p, imuconv::test::Plugins(), o), json::parse(serial));
  }
}

TEST(Parallel, FailuresAreTheSameForAnyThreadCount) {
  // Every interval overflows (a start covariance of 1e308, unchained): the first one in
  // output order is reported, whichever thread got to which interval first.
  json doc = imuconv::test::ReadJson(SourcePath("examples/inline_basics.json"));
  json& pbp = doc["tasks"][3];
  ASSERT_EQ(pbp["type"], "propagate_by_preintegration");
  json sigma = json::array();
  for (int i = 0; i < 15; ++i) sigma.push_back(1e154);
  pbp["start"]["cov"] = {{"sigma", sigma}};
  pbp["chain"] = false;
  const Pipeline p = Pipeline::FromJson(doc, "overflow.json", SourcePath("examples"));
  std::set<std::string> messages;
  for (unsigned threads : {1u, 2u, 4u}) {
    messages.insert(imuconv::test::MessageOf<Error>([&] { RunText(p, threads); }));
  }
  ASSERT_EQ(messages.size(), 1u);
  EXPECT_NE(messages.begin()->find("overflow.json: /tasks/3 (task 'by_preint'): produced a "
                                   "non-finite number (output /tasks/3/steps/0/cov/matrix/"),
            std::string::npos)
      << *messages.begin();
}

TEST(Parallel, AFailingSinkIsReportedAsItself) {
  // The output is streamed while tasks run: an error of the sink (a full disk) is reported
  // with its own message, not as a failure of the task that was running.
  const Pipeline p = Pipeline::Load(SourcePath("examples/euroc_v1_01_keyframes.json"));
  for (unsigned threads : {1u, 3u}) {
    int calls = 0;
    RunOptions o;
    o.threads = threads;
    const std::string msg = imuconv::test::MessageOf<Error>([&] {
      RunToText(p, imuconv::test::Plugins(), o, [&](std::string_view) {
        if (++calls == 2)
          throw Error("out.json: cannot write the temporary file: No space left on device");
      });
    });
    EXPECT_EQ(msg, "out.json: cannot write the temporary file: No space left on device");
    EXPECT_EQ(calls, 2);
  }
}

TEST(Parallel, CommandLineThreadsGiveTheSameFile) {
  imuconv::test::TempDir tmp;
  const std::string pipeline =
      imuconv::test::ShellQuote(SourcePath("examples/euroc_v1_01_keyframes.json"));
  std::vector<std::string> texts;
  for (const char* threads : {"1", "2", "4"}) {
    const std::string out = tmp.file(std::string("out") + threads + ".json");
    const auto r =
        imuconv::test::RunImuconv("run " + pipeline + " -o " + imuconv::test::ShellQuote(out) +
                                      " --quiet --threads " + threads,
                                  tmp);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    texts.push_back(imuconv::test::ReadText(out));
  }
  ASSERT_GT(texts[0].size(), 1000000u);
  EXPECT_TRUE(texts[1] == texts[0]);
  EXPECT_TRUE(texts[2] == texts[0]);
  const auto bad = imuconv::test::RunImuconv("run " + pipeline + " --threads many", tmp);
  EXPECT_EQ(bad.exit_code, 2) << bad.err;
}

TEST(Parallel, WholeEurocFile) {
  // The whole V1_01_easy IMU file (29120 samples, 145.6 s): 1447 keyframe intervals of
  // 0.1 s where the ground truth exists (0 to 144.7 s), RK4 preintegration by propagation
  // expressed in gtsam_manifold, each propagated from the ground truth at its start.
  const Pipeline p = Pipeline::Load(SourcePath("examples/euroc_v1_01_full.json"));
  std::string summary;
  const std::string text = RunText(p, 0, &summary);
  EXPECT_TRUE(RunText(p, 1) == text) << "serial and parallel runs differ";
  const json out = json::parse(text);
  EXPECT_EQ(out["time_origin_ns"].get<std::int64_t>(), 1403715273262142976LL);
  // Only the samples the tasks integrate over are kept in memory: the 28941 samples at 200 Hz
  // in [0, 144.7] s and the next one (the file has 29120, to 145.6 s). The ground truth ends
  // at 144.7 s: every row is in the range.
  EXPECT_EQ(out["imu"]["samples"], 28942);
  EXPECT_EQ(out["imu"]["kept_range"], json({0.0, 144.7}));
  EXPECT_EQ(out["ground_truth"]["rows"], 2895);
  const json& ms = TaskOutput(out, "kf_rk4")["measurements"];
  ASSERT_EQ(ms.size(), 1447u);
  for (std::size_t k = 0; k < ms.size(); ++k) {
    ASSERT_EQ(ms[k]["t_start_abs_ns"].get<std::int64_t>(),
              1403715273262142976LL + static_cast<std::int64_t>(k) * 100000000LL);
    ASSERT_NEAR(ms[k]["dt"].get<double>(), 0.1, 1e-12);
    ASSERT_EQ(ms[k]["n_knots"], 21);  // 200 Hz samples on the keyframes: 20 steps
    ASSERT_TRUE(ms[k]["expressed"].contains("gtsam_manifold"));
  }
  const json& pred = TaskOutput(out, "pred_rk4");
  ASSERT_EQ(pred["steps"].size(), 1447u);
  EXPECT_EQ(pred["steps"][1446]["cov"]["convention"], "left");
  // Over the whole sequence, as on the 20 s slice (examples.cpp: observed RMS 0.29 mm /
  // 0.013 deg there; here 0.27 mm / 0.015 deg RMS, 0.74 mm / 0.043 deg max): same bounds.
  const json& s = pred["ground_truth_summary"];
  EXPECT_EQ(s["intervals"], 1447);
  EXPECT_LT(s["rms_position_error_m"].get<double>(), 1.5e-3);
  EXPECT_LT(s["rms_rotation_error_deg"].get<double>(), 0.08);
  EXPECT_LT(s["max_position_error_m"].get<double>(), 4e-3);
  EXPECT_LT(s["max_rotation_error_deg"].get<double>(), 0.3);
  EXPECT_NE(summary.find(" total (1447)       144.7000"), std::string::npos)
      << summary.substr(summary.size() - 600);
}

}  // namespace
