// GTSAM's zero-order-hold ManifoldPreintegration numbers for a reference case
// (tests/data/reference/gtsam) as a measurements document for imuconv check, every chart
// declared: consistent with the euler scheme over all the case's samples. The check tests plant
// their defects in it.
#pragma once

#include <Eigen/Core>
#include <nlohmann/json.hpp>
#include <string>

#include "imuconv_test.h"
#include "reference_case.h"

namespace imuconv::test {

/// J_bias rows [theta, p, v] columns [ba, bg] (the chart gtsam_manifold names), cov15 in
/// gtsam_manifold [theta, p, v, ba, bg]; both are also returned as matrices where asked.
inline nlohmann::json GtsamMeasurement(const std::string& id, Eigen::MatrixXd* J = nullptr,
                                       Eigen::MatrixXd* cov = nullptr) {
  const nlohmann::json c = CaseJson(id);
  const nlohmann::json g = GtsamReferenceJson(id);
  const nlohmann::json& s = g["zoh"]["manifold"];
  if (J) *J = JsonMatrix(s["J_bias"]);
  if (cov) *cov = JsonMatrix(s["cov15"]);
  return {{"t_start", c["imu"].front()[0]},
          {"t_end", c["imu"].back()[0]},
          {"dt", s["deltaT"]},
          {"bias_estimate", {{"bg", c["state_s"]["bg"]}, {"ba", c["state_s"]["ba"]}}},
          {"delta", {{"R", s["deltaR"]}, {"dp", s["deltaP"]}, {"dv", s["deltaV"]}}},
          {"J_bias", {{"matrix", s["J_bias"]}}},
          {"cov",
           {{"convention", "gtsam_manifold"},
            {"blocks", {"theta", "p", "v", "ba", "bg"}},
            {"matrix", s["cov15"]}}}};
}

}  // namespace imuconv::test
