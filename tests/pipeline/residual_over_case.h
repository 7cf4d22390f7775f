// What the residual kinds' tests against the systems' own evaluations (residual_native.cpp,
// residual_okvis2.cpp, residual_orb_slam3.cpp) share: a pipeline over a whole reference case,
// its samples inline, that preintegrates the case's whole interval and evaluates residual tasks
// on that measurement with an anchor's own states, run in memory, through the pipeline's path
// (the measurement through the registry, the states through the pipeline's state form).
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "imuconv/pipeline/pipeline.h"
#include "imuconv_test.h"

namespace imuconv::test {

/// A "preintegrate" task `name` over [t0, t1] (keyframes) with the preintegrator
/// `preintegrator`, at the bias estimate {bg, ba} of `bias` (a state or bias object).
inline nlohmann::json PreintegrateTask(const char* name, const char* preintegrator,
                                       const nlohmann::json& bias, double t0, double t1) {
  return {{"type", "preintegrate"},
          {"name", name},
          {"method", {{"preintegrator", preintegrator}}},
          {"bias", {{"bg", bias.at("bg")}, {"ba", bias.at("ba")}}},
          {"keyframes", {t0, t1}}};
}

/// A "residual" task `name` of kind `kind` on the measurement of the task `measurements`,
/// between the states `start` and `end` (the pipeline's state form).
inline nlohmann::json ResidualTask(const char* name, const char* kind, const char* measurements,
                                   const nlohmann::json& start, const nlohmann::json& end) {
  return {{"type", "residual"},           {"name", name},   {"kind", kind},
          {"measurements", measurements}, {"start", start}, {"end", end}};
}

/// An anchor's state as the pipeline's state form: its position under `position_key` ("p";
/// OKVIS writes "r"), q_wxyz, v, bg, ba as they are.
inline nlohmann::json AnchorStateJson(const nlohmann::json& x, const char* position_key = "p") {
  return {{"p", x.at(position_key)},
          {"q_wxyz", x.at("q_wxyz")},
          {"v", x.at("v")},
          {"bg", x.at("bg")},
          {"ba", x.at("ba")}};
}

/// The output of a pipeline over the reference case `c` (its noise, gravity and samples,
/// inline) running `tasks`, run in memory on one thread; `label` names it in messages.
inline nlohmann::json RunOverCase(const nlohmann::json& c, const nlohmann::json& tasks,
                                  const std::string& label) {
  const nlohmann::json doc = {{"noise", c.at("noise")},
                              {"gravity", c.at("gravity")},
                              {"imu", {{"format", "inline"}, {"samples", c.at("imu")}}},
                              {"tasks", tasks}};
  const pipeline::Pipeline p = pipeline::Pipeline::FromJson(doc, label, ".");
  pipeline::RunOptions o;
  o.threads = 1;
  return pipeline::Run(p, Plugins(), o);
}

}  // namespace imuconv::test
