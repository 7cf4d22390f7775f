#include "comparison.h"

#include <string>
#include <vector>

#include "chart_matrix.h"
#include "imuconv/reference_charts.h"
#include "imuconv/so3.h"
#include "increment.h"
#include "state.h"

namespace imuconv::pipeline {

double RotationErrorDeg(const Mat3& a, const Mat3& b) {
  return RotationAngleDeg(a.transpose() * b);
}

GtComparison Compare(const ImuState& pred, const ImuState& gt, bool full_state) {
  GtComparison c;
  c.gt = gt;
  c.full_state = full_state;
  c.e.pos = (pred.p - gt.p).norm();
  c.e.rot = RotationErrorDeg(gt.R, pred.R);
  if (full_state) {
    c.e.vel = (pred.v - gt.v).norm();
    LeftLocal(gt, pred, c.d);
  }
  return c;
}

void WriteComparison(JsonWriter& w, const GtComparison& c) {
  static const std::vector<std::string> kLeftBlocks = {"p", "theta", "v", "bg", "ba"};
  w.begin_object();
  if (c.full_state) {
    w.key("state");
    WriteState(w, c.gt);
  } else {
    // A pose: what the ground truth holds, nothing made up for velocity and biases.
    w.key("pose");
    w.begin_object();
    w.key("p");
    w.vector(c.gt.p);
    w.key("q_wxyz");
    w.vector(so3::ToQuaternionWxyz(c.gt.R));
    w.end_object();
  }
  w.key("position_error_m");
  w.number(c.e.pos);
  w.key("rotation_error_deg");
  w.number(c.e.rot);
  if (c.full_state) {
    w.key("velocity_error_mps");
    w.number(*c.e.vel);
    w.key("error_left");
    WriteChartVector(w, c.d, "left", kLeftBlocks);
  }
  w.end_object();
}

}  // namespace imuconv::pipeline
