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
#include <string>
#include <vector>

#include "imuconv/registry.h"

namespace imuconv::refcase {

/// A reference case, read and checked by ParseCase.
struct Case {
  std::vector<ImuSample> samples;
  Vec3 gravity;
  ImuNoise noise;
  ImuState x_s;
  Eigen::Vector4d q_s_wxyz;  ///< state_s's quaternion as written (sign kept; unit within 1e-6)
  Mat15 cov_s_left;
  Vec15 end_perturbation;
  Vec3 dbg, dba;
};

/// Reads a case with the rules of Run below; throws imuconv::Error naming the JSON pointer.
Case ParseCase(const nlohmann::json& case_json);

/// Which keys ParseCase below must find.
enum class CaseKeys {
  all_required,  ///< every key (a reference computation uses them all)
  /// /imu and /noise only; the others take their standard values (case_keys.cpp, FORMAT.md):
  /// gravity [0, 0, -9.81], the identity start state with zero bias estimate, a zero start
  /// covariance, end perturbation and bias_delta. For a command that does not use them.
  samples_and_noise,
};

/// As ParseCase above, with every missing key named in one error (all of them at once,
/// "/gravity, /state_s/q_wxyz: missing ..."), and under samples_and_noise the others filled
/// with their standard values, their pointers appended to `defaulted` when given.
Case ParseCase(const nlohmann::json& case_json, CaseKeys keys,
               std::vector<std::string>* defaulted = nullptr);

/// Refuses a computed document with a non-finite number or a covariance ("cov15", "cov9",
/// "cov", "covariance", "Qd_summed") with a variance below -1e-9 of the largest, naming the
/// output pointer under `ptr`.
void CheckResults(const nlohmann::json& out, const std::string& ptr);

/// GTSAM's `mid` input (tests/data/reference/FORMAT.md): the mean of knots k and k+1, held by
/// a zero-order-hold scheme over [t_k, t_k+1], at the same times, fed as a new sample sequence.
/// The last knot keeps its value; a zero-order hold never uses it. The cases' mid.* results and
/// imuconv experiment's --input mid are both made from it.
std::vector<ImuSample> MidSampleInput(const std::vector<ImuSample>& samples);

/// A matrix as an array of rows, a vector as an array.
nlohmann::json ToJson(const Eigen::MatrixXd& m);
nlohmann::json ToJsonVec(const Eigen::VectorXd& v);

/// Throws imuconv::Error naming the JSON pointer of a missing, unknown or malformed field,
/// with the rules of `imuconv run`: finite numbers, a unit quaternion (within 1e-6), a valid
/// covariance (imuconv::CovarianceProblem), non-negative noise densities, increasing times,
/// and the layout labels (imu_columns, cov_s_left/order), when given, as FORMAT.md has them.
/// A result that is not finite, or a computed variance below -1e-9 of the largest, is refused
/// naming its output pointer; nothing is repaired or written as null.
nlohmann::json Run(const Registry& reg, const nlohmann::json& case_json);

}  // namespace imuconv::refcase
