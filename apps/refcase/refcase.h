// Reference-case runner: reads a case in the format of tests/data/reference/FORMAT.md and
// produces its results in exactly the layout of the GTSAM reference files, by running the
// ordinary bridge operations:
//   zoh.manifold  euler integrator, preintegration by propagation, into gtsam_manifold
//   zoh.tangent   native `tangent` preintegrator, gtsam_tangent
//   mid.manifold  rk4, preintegration by propagation, into gtsam_manifold
//   mid.tangent   rk4, preintegration by propagation, into gtsam_tangent
// plus a `propagation` block per integrator (end state, Phi and covariance in `left` from
// cov_s_left) and, for the zoh.manifold measurement, Phi and Sigma_e|s by preintegration.
#pragma once

#include <nlohmann/json.hpp>

#include "imuconv/registry.h"

namespace imuconv::refcase {

/// Throws imuconv::Error naming the JSON pointer of a missing or malformed field.
nlohmann::json Run(const Registry& reg, const nlohmann::json& case_json);

}  // namespace imuconv::refcase
