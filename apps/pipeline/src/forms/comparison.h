// The ground-truth comparison form of a predicted state:
//   {"state": STATE, "position_error_m", "rotation_error_deg", "velocity_error_mps",
//    "error_left": {"convention": "left", "blocks", "vector"}}
// and against pose-only ground truth (TUM, EuRoC vicon0), what a pose can tell:
//   {"pose": {"p", "q_wxyz"}, "position_error_m", "rotation_error_deg"}
#pragma once

#include <optional>

#include "imuconv/pipeline/json_writer.h"
#include "imuconv/types.h"

namespace imuconv::pipeline {

struct GtError {
  double pos = 0, rot = 0;    ///< m, deg
  std::optional<double> vel;  ///< m/s, when the ground truth has velocity
};

/// A prediction against the ground truth: the errors and (full state) the left-chart error
/// vector.
struct GtComparison {
  ImuState gt;
  bool full_state = true;
  GtError e;
  Vec15 d = Vec15::Zero();
};

/// `full_state`: whether ground_truth's velocity and biases are known (false for poses).
GtComparison Compare(const ImuState& predicted, const ImuState& ground_truth,
                     bool full_state = true);
void WriteComparison(JsonWriter& w, const GtComparison& c);

/// The angle of a^T b in degrees.
double RotationErrorDeg(const Mat3& a, const Mat3& b);

}  // namespace imuconv::pipeline
