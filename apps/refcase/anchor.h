// imuconv refcase CASE.json --anchor NAME: the computed fields of the files of
// tests/data/reference/anchors/NAME/ (README.md there), computed by imuconv from the case with
// the anchor's own input conventions, in the same names and layout (not `inputs`, `upstream`
// and `build`, which describe the upstream run):
//   vins-fusion  IntegrationBase with the case's densities used as configured (ACC_N = the
//                accelerometer density, ...), the start biases as linearization point, G =
//                -gravity; evaluate(), IMUFactor::Evaluate raw and whitened, the bias correction
//                and repropagate (kernels/vins_fusion.h, vins_fusion_residual.h);
//   basalt       IntegratedImuMeasurement in both feedings with the per-sample variances of
//                Basalt's VIO at the nominal rate imu_update_rate = 200 (sigma^2 200); residual()
//                at the linearization and the new bias (kernels/basalt.h, basalt_residual.h);
//   openvins     each integration method whose propagator is registered (`openvins_discrete`,
//                `openvins_rk4`, `openvins_analytical`, looked up by id at run time) in the
//                `openvins_jpl` error state from P0 = cov_s_left in that chart; the document's
//                `methods_written` and `methods_missing` say which.
// Each writer is one file of anchors/ (anchors/anchor_writer.h: a new system adds its file
// there and edits nothing else). The residuals' end states follow the anchors' recipe: the system's
// own prediction from state_s retracted by end_perturbation (R^ Exp(dth), p^ + R^ dp, v^ + R^ dv,
// biases added).
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "imuconv/registry.h"

namespace imuconv::refcase {

/// The NAMEs RunAnchor accepts.
const std::vector<std::string>& AnchorNames();

/// Throws imuconv::Error for an unknown name, a case that fails ParseCase's checks (naming
/// the JSON pointer) or a result refused by CheckResults.
nlohmann::json RunAnchor(const Registry& reg, const nlohmann::json& case_json,
                         const std::string& name);

}  // namespace imuconv::refcase
