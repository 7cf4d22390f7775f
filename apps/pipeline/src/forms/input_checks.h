// The checks every numeric input of a pipeline goes through, wherever it is read (pipeline
// document, measurement file): one rule for rotations and one for covariances, so that no
// reader has a looser path (internal to imuconv_pipeline).
#pragma once

#include <optional>
#include <string>

#include "imuconv/numeric.h"
#include "imuconv/pipeline/json_check.h"
#include "imuconv/registry.h"
#include "imuconv/types.h"

namespace imuconv::pipeline {

/// A quaternion must have unit norm within this (then it is normalised). JSON numbers
/// written with 7 or more significant digits stay well inside it; an all-zero, a doubled or
/// a truncated ("0.7, 0.7") quaternion does not.
constexpr double kUnitQuaternionTol = 1e-6;
/// A rotation matrix: R^T R = I within this, entrywise, and det R > 0.
constexpr double kRotationMatrixTol = 1e-6;

/// [w, x, y, z] at `n` as a rotation matrix, or nothing (the error reported at n's pointer).
std::optional<Mat3> RotationFromQuaternion(const Node& n);
/// OpenVINS's JPL q_GtoI [x, y, z, w] at `n` as the body-to-world rotation matrix, or nothing.
std::optional<Mat3> RotationFromJplQuaternion(const Node& n);
/// A 3x3 rotation matrix at `n`, re-orthonormalised, or nothing (the error reported).
std::optional<Mat3> RotationFromMatrix(const Node& n);

/// The tolerance of CovarianceProblem for numbers computed in single precision (a measurement
/// whose "precision" is "float32", measurement.h). float32's unit round-off is 6e-8; a
/// covariance accumulated over N steps in it carries errors of order sqrt(N) 6e-8 (2.7e-6 at
/// N = 2000, 6e-5 at 1e6 steps), and C_ij and C_ji are rounded separately, so its asymmetry is
/// of that order (ORB-SLAM3's, 2000 steps: 3e-9 on the correlation scale). 1e-4 passes that
/// and lies 100 times below imuconv check's 1e-2 on the same scale, so an asymmetry it passes
/// cannot change a verdict; a real defect (a sign, a transposed block) is of order 1e-3 or more.
inline constexpr double kCovarianceTolFloat32 = 1e-4;

/// "" or what is wrong with C as a covariance input: imuconv::CovarianceProblem with `tol`
/// (kCovarianceTol: numbers in double precision; kCovarianceTolFloat32), plus the smallest
/// eigenvalue when the problem does not already give it.
std::string CovarianceInputProblem(const Mat15& C, double tol = kCovarianceTol);
/// Reports CovarianceInputProblem(C, tol) at `pointer` (nothing is repaired); true when C is fine.
bool CheckCovarianceInput(Checker& c, const std::string& pointer, const Mat15& C,
                          double tol = kCovarianceTol);

/// A covariance the pipeline computed and is about to write at output `pointer`: throws
/// imuconv::Error when a variance is negative beyond round-off (kCovarianceTol times the
/// largest variance). From valid inputs that is a defect of imuconv or of a plugin, to be
/// reported, never written.
void CheckOutputCovariance(const Mat15& C, const std::string& pointer);

/// Reports an unknown plugin id at `pointer` with the known ids of that kind (and, for a
/// frequent slip, the kind the id does have).
void CheckPluginId(Checker& c, const Registry& reg, PluginKind kind, const std::string& id,
                   const std::string& pointer);

}  // namespace imuconv::pipeline
