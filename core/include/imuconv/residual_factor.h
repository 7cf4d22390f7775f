// ResidualFactor: a system's own IMU factor (its residual, Jacobians and weighting) as its
// optimizer receives it, in the system's layout and parameter increments (VINS-Fusion's
// IMUFactor::Evaluate, Basalt's IntegratedImuMeasurement::residual, OKVIS2's ImuError, ...).
// The registry's generic residuals (bridge.h, ResidualKind gtsam and forster) are written in
// charts imuconv names; a factor is not: its Jacobians are w.r.t. the system's own blocks (a
// 7-dim quaternion pose, a 9-dim state without biases), so it writes them under its own names
// through a ResidualSink the host implements.
//
// The measurement reaches evaluate() already expressed in increment_convention() (the host
// converts it with the registry, from whatever preintegrator produced it), so any
// measurement can be judged by any system's factor. Nothing crosses the boundary but plain
// data: the sink's arguments are C strings and arrays of doubles, every function is noexcept
// and errors come back as Status.
#pragma once

#include <Eigen/Core>

#include "imuconv/preintegrated.h"
#include "imuconv/residual_cost_spec.h"
#include "imuconv/status.h"
#include "imuconv/types.h"

namespace imuconv {

/// Where a factor writes what it computes; implemented by the host (the pipeline writes JSON,
/// `imuconv plugins --check` only checks). Names are members of the open group: non-empty
/// UTF-8, each at most once per group. Arrays are read at once; the sink keeps no pointer.
/// A sink that cannot take a value (a bad name, a non-finite number, a size out of bounds)
/// records the first such problem and ignores what follows; the host reports it after
/// evaluate() returns, naming the plugin.
class ResidualSink {
 public:
  /// Opens a nested group `name` inside the open one; closed by end_group().
  virtual void begin_group(const char* name) noexcept = 0;
  virtual void end_group() noexcept = 0;
  /// A vector of `size` numbers (written as one array).
  virtual void vector(const char* name, const double* values, int size) noexcept = 0;
  /// A rows x cols matrix, `row_major` holding row 0 first (written as an array of rows).
  virtual void matrix(const char* name, const double* row_major, int rows, int cols) noexcept = 0;
  /// The squared Mahalanobis distance r^T Sigma^-1 r of the factor's residual under its own
  /// weighting, with degrees_of_freedom() degrees of freedom; at most once per evaluation,
  /// and not at all where the weighting does not exist (a measurement without noise).
  virtual void mahalanobis_squared(double value) noexcept = 0;

 protected:
  ~ResidualSink() = default;
};

class ResidualFactor {
 public:
  virtual ~ResidualFactor() = default;
  virtual const char* id() const noexcept = 0;
  /// The increment convention (a registered id) the measurement is expressed in before
  /// evaluate() sees it: its cov and J_bias are in that chart and block order.
  virtual const char* increment_convention() const noexcept = 0;
  /// What the numbers are: the system's function, block orders, parameter increments and how
  /// the states and the measurement enter (UTF-8; written once per task as "layout").
  virtual const char* layout() const noexcept = 0;
  /// Degrees of freedom of mahalanobis_squared (the residual's dimension).
  virtual int degrees_of_freedom() const noexcept = 0;
  /// The factor of measurement `m` (in increment_convention()) between the start state x_s
  /// (whose biases are the current estimate) and the end state x_e, under `gravity` (world
  /// frame, e.g. (0, 0, -9.81)): writes its named values to `sink`.
  virtual Status evaluate(const Preintegrated& m, const ImuState& x_s, const ImuState& x_e,
                          const Vec3& gravity, ResidualSink& sink) const noexcept = 0;
  /// How evaluate()'s outputs form a least-squares cost (residual_cost_spec.h), or nullptr for a
  /// factor that declares none (ABI version 4). The object lives as long as the plugin.
  virtual const ResidualCostSpec* cost_spec() const noexcept { return nullptr; }
};

/// A fixed-size Eigen vector to the sink (plugin side).
template <class Derived>
void WriteVector(ResidualSink& sink, const char* name, const Eigen::MatrixBase<Derived>& v) {
  const Eigen::Matrix<double, Derived::SizeAtCompileTime, 1> copy = v;
  sink.vector(name, copy.data(), static_cast<int>(copy.size()));
}

/// A fixed-size Eigen matrix to the sink, row-major (plugin side).
template <class Derived>
void WriteMatrix(ResidualSink& sink, const char* name, const Eigen::MatrixBase<Derived>& m) {
  constexpr int R = Derived::RowsAtCompileTime, C = Derived::ColsAtCompileTime;
  const Eigen::Matrix<double, R, C, (C == 1 && R != 1) ? Eigen::ColMajor : Eigen::RowMajor> copy =
      m;
  sink.matrix(name, copy.data(), R, C);
}

}  // namespace imuconv
