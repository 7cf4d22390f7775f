// libFuzzer target: the measurements import (the file format that propagate_by_preintegration,
// residual and bias_update read, and that a preintegrate task writes), through a fixed
// pipeline that names the fuzzed file. Every measurement read is used: propagated, turned into
// residuals against a fixed state, and bias-corrected to first order.
#include <string_view>

#include "fuzz_support.h"
#include "imuconv/pipeline/pipeline.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace imuconv;
  using nlohmann::json;
  static fuzz::InputFile file("measurements.json");
  const Registry& reg = fuzz::LoadedRegistry();
  const std::string& path = file.write(data, size);
  const json state = {{"p", {0, 0, 0}}, {"q_wxyz", {1, 0, 0, 0}}, {"v", {0, 0, 0}}};
  const json doc = {
      {"noise",
       {{"gyro_noise_density", 1e-4},
        {"accel_noise_density", 1e-3},
        {"gyro_random_walk", 1e-5},
        {"accel_random_walk", 1e-4}}},
      {"tasks",
       {{{"type", "propagate_by_preintegration"},
         {"name", "prop"},
         {"measurements", {{"file", path}}},
         {"start", {{"state", state}, {"cov", {{"diagonal", std::vector<double>(15, 1e-4)}}}}}},
        {{"type", "residual"},
         {"name", "res"},
         {"kind", "gtsam"},
         {"measurements", {{"file", path}}},
         {"index", 0},
         {"start", state},
         {"end", state}},
        {{"type", "bias_update"},
         {"name", "bias"},
         {"measurements", {{"file", path}}},
         {"reintegrate", false},
         {"bias", {{"delta_bg", {1e-3, 0, 0}}, {"delta_ba", {0, 1e-2, 0}}}},
         {"first_order_charts",
          {"preint_reference", "gtsam_manifold", "gtsam_tangent", "forster"}}}}}};
  fuzz::Expect(
      [&] {
        const pipeline::Pipeline p = pipeline::Pipeline::FromJson(doc, "(fuzz pipeline)", "/");
        pipeline::RunOptions options;
        options.threads = 1;
        pipeline::RunToText(p, reg, options, [](std::string_view) {});
      },
      "");
  return 0;
}
