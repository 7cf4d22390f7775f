// The ground-truth comparison form of a predicted state:
//   {"state": STATE, "position_error_m", "rotation_error_deg", "velocity_error_mps",
//    "error_left": {"convention": "left", "blocks", "vector"}}
#pragma once

#include "imuconv/pipeline/json_writer.h"
#include "imuconv/types.h"

namespace imuconv::pipeline {

struct GtError {
  double pos = 0, rot = 0, vel = 0;  ///< m, deg, m/s
};

/// A prediction against the ground truth: the errors and the left-chart error vector.
struct GtComparison {
  ImuState gt;
  GtError e;
  Vec15 d = Vec15::Zero();
};

GtComparison Compare(const ImuState& predicted, const ImuState& ground_truth);
void WriteComparison(JsonWriter& w, const GtComparison& c);

/// The angle of a^T b in degrees.
double RotationErrorDeg(const Mat3& a, const Mat3& b);

}  // namespace imuconv::pipeline
