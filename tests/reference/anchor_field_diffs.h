// The worst differences of one run's fields against an anchor file (tests/data/reference/
// anchors), each checked as it is compared and printed once under a label: by the note's
// metric for every field, and on the scale each kind of matrix needs (anchors.h says why).
#pragma once

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cstdio>
#include <optional>
#include <string>
#include <utility>

#include "anchors.h"
#include "imuconv_test.h"
#include "json_quaternion.h"
#include "scale_aware.h"

namespace imuconv::test {

/// A quaternion as the anchors write it, [w, x, y, z].
inline Eigen::Vector4d Wxyz(const Eigen::Quaterniond& q) { return {q.w(), q.x(), q.y(), q.z()}; }

class AnchorFieldDiffs {
 public:
  /// `metric_tol`: the bound by the note's metric (the anchors' 1e-8; a single-precision
  /// original gets its own).
  explicit AnchorFieldDiffs(std::string label, double metric_tol = kAnchorMetricTol)
      : label_(std::move(label)), metric_tol_(metric_tol) {}

  /// Any field, by the note's metric.
  template <typename A, typename B>
  void Metric(const char* field, const A& ref, const B& est) {
    const double d = MaxEntryDiff(ref, est);
    EXPECT_LE(d, metric_tol_) << label_ << ": " << field;
    if (d > metric_) {
      metric_ = d;
      worst_field_ = field;
    }
  }
  /// A field of a single-precision original: by the note's metric where the original's
  /// arithmetic is reproduced operation for operation, else relative to the field's largest
  /// entry (float rounding, about 6e-8 of each product, is no longer small beside an entry far
  /// below the largest).
  template <typename A, typename B>
  void Float(const char* field, const A& ref, const B& est, bool operation_for_operation) {
    if (operation_for_operation) return Metric(field, ref, est);
    const double largest = std::max(ref.cwiseAbs().maxCoeff(), 1e-300);
    const double d = (ref - est).cwiseAbs().maxCoeff() / largest;
    EXPECT_LE(d, metric_tol_) << label_ << ": " << field << " (relative to its largest entry)";
    if (d > metric_) {
      metric_ = d;
      worst_field_ = field;
    }
  }
  /// A Jacobian or transition: also relative to each entry above 1e-4 of the largest.
  template <typename A, typename B>
  void Jacobian(const char* field, const A& ref, const B& est) {
    Metric(field, ref, est);
    Scaled(field, RelativeAboveFloorDiff(ref, est));
  }
  /// A covariance: also on its correlation scale.
  template <typename A, typename B>
  void Covariance(const char* field, const A& ref, const B& est) {
    Metric(field, ref, est);
    Scaled(field, CorrelationScaleDiff(ref, est));
  }
  /// The names a system's anchor files give the end state's position, rotation quaternion
  /// [w, x, y, z], rotation matrix and velocity (its biases are `bg` and `ba` in every file).
  struct StateKeys {
    const char* p;
    const char* q_wxyz;
    const char* R;
    const char* v;
  };
  /// A propagated end state against the file's `e`: position, rotation (the quaternion where
  /// the run compares one) and velocity by the note's metric, and the biases exactly
  /// (propagation carries them unchanged).
  void PropagatedState(const nlohmann::json& e, const StateKeys& keys, const Vec3& p,
                       const std::optional<Eigen::Vector4d>& q_wxyz, const Mat3& R, const Vec3& v,
                       const Vec3& bg, const Vec3& ba) {
    Metric(keys.p, JsonMatrix(e.at(keys.p)), p);
    if (q_wxyz) Metric(keys.q_wxyz, JsonMatrix(e.at(keys.q_wxyz)), *q_wxyz);
    Metric(keys.R, JsonMatrix(e.at(keys.R)), R);
    Metric(keys.v, JsonMatrix(e.at(keys.v)), v);
    EXPECT_EQ(JsonVec3(e.at("bg")), bg);
    EXPECT_EQ(JsonVec3(e.at("ba")), ba);
  }
  void Print() const {
    std::printf("  %-36s metric %.2g (%s) scaled %.2g\n", label_.c_str(), metric_,
                worst_field_.c_str(), scaled_);
  }

 private:
  void Scaled(const char* field, const ScaledDiff& s) {
    EXPECT_LE(s.d, kAnchorScaledTol)
        << label_ << ": " << field << " at (" << s.row << "," << s.col << ")";
    scaled_ = std::max(scaled_, s.d);
  }
  std::string label_;
  double metric_tol_;
  double metric_ = 0.0, scaled_ = 0.0;
  std::string worst_field_ = "-";
};

}  // namespace imuconv::test
