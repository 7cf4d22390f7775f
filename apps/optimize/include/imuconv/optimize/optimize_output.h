// What imuconv optimize prints: one JSON object (--json; its keyframes as the list `keyframes`,
// docs/optimize.md) or the human table.
#pragma once

#include <nlohmann/json.hpp>
#include <ostream>

#include "imuconv/optimize/optimize.h"

namespace imuconv::optimize {

/// Each keyframe's t, p, q_wxyz, v, bg, ba and 15x15 covariance (null when it was not computed),
/// the block labels of the covariance, the solver summary with its rounds, and the biases against
/// the reference's when the poses file has them.
nlohmann::json ResultJson(const Result& r);

/// The solver summary's rounds, one object per solve (iterations, initial_cost, final_cost,
/// termination, seconds, reintegrated): the --json output's solver.rounds, and imuconv.optimize's.
nlohmann::json RoundsJson(const Result& r);
/// The rounds' iterations and seconds added up (solver.iterations and solver.seconds).
int TotalIterations(const Result& r);
double TotalSeconds(const Result& r);

/// A keyframe's attitude as the output's q_wxyz: the unit quaternion of R with w >= 0 (the
/// --json output's keyframes and imuconv.optimize's rows, so that the two give the same bits).
Eigen::Vector4d UnitQuaternionWxyz(const Mat3& R);

/// The summary and one row per keyframe (its biases with their 1-sigma).
void PrintTable(std::ostream& out, const Result& r);

}  // namespace imuconv::optimize
