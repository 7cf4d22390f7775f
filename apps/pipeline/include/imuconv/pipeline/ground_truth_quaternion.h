// The one rule for a ground-truth quaternion read as numbers (EuRoC and TUM files, pose arrays
// given to imuconv.optimize): unit within kGroundTruthQuaternionNormTol, then normalised.
#pragma once

#include <cmath>
#include <cstdio>
#include <optional>
#include <string>

namespace imuconv::pipeline {

/// 1e-3: ground-truth files write quaternions with 6 significant digits (EuRoC's) or fewer
/// (three digits leave a norm off by up to ~1e-3 / 2); a norm further from 1 is a damaged or
/// misread row (a swapped column, a dropped digit), not rounding. Tighter than this would refuse
/// the recorded files; the JSON state reader's 1e-6 is for numbers a program printed in full.
inline constexpr double kGroundTruthQuaternionNormTol = 1e-3;

/// Why the quaternion (w, x, y, z) is not a ground-truth rotation, or nothing: "quaternion
/// (q_w, q_x, q_y, q_z) has norm 1.002, expected 1 (to 1e-3)". `layout` names the fields in
/// the order the source gives them.
inline std::optional<std::string> GroundTruthQuaternionProblem(double qw, double qx, double qy,
                                                               double qz, const char* layout) {
  const double norm = std::sqrt(qw * qw + qx * qx + qy * qy + qz * qz);
  if (std::abs(norm - 1.0) <= kGroundTruthQuaternionNormTol) return std::nullopt;
  char text[32];
  std::snprintf(text, sizeof text, "%g", norm);
  return std::string("quaternion ") + layout + " has norm " + text + ", expected 1 (to 1e-3)";
}

}  // namespace imuconv::pipeline
