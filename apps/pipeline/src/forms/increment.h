// The increment form ("delta" of a measurement, "increment" of a convert task):
//   {"q_wxyz": [4] and/or "R": [[3x3]], "dp": [3], "dv": [3], "dbg"?: [3], "dba"?: [3],
//    "rotation_angle_deg"?: number}
// ONE reader for every place an increment is read, and its writer beside it.
#pragma once

#include <optional>

#include "imuconv/pipeline/json_check.h"
#include "imuconv/pipeline/json_writer.h"
#include "imuconv/types.h"

namespace imuconv::pipeline {

/// Reads an increment. The rotation may be given as q_wxyz, as R, or both; every statement
/// (q_wxyz, R, rotation_angle_deg) is checked (unit quaternion within 1e-6, rotation matrix
/// within 1e-6) and they must agree within 1e-6 deg: none silently wins over another. dbg and
/// dba default to zero. Nothing (errors reported at their pointers) if anything is wrong.
std::optional<PreintIncrement> IncrementFromJson(const Node& n);

/// Writes an increment: q_wxyz, R (unless `with_R` is false: the "omit": ["R"] option), dp,
/// dv, dbg, dba and rotation_angle_deg. What it writes, IncrementFromJson reads back.
void WriteIncrement(JsonWriter& w, const PreintIncrement& d, bool with_R = true);

/// |Log(R)| in degrees.
double RotationAngleDeg(const Mat3& R);

}  // namespace imuconv::pipeline
