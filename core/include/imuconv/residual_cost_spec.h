// How a residual plugin's outputs (residual_factor.h) form a least-squares cost: which vector
// is the residual, how the system's own solver whitens it, and which columns of which of its
// Jacobians differentiate by which 3-block of a registered state convention. The plugin
// declares it once, as plain data (C strings, ints, the Block enum), so that a host can build
// a cost for any residual plugin (imuconv::ceres, NativeResidualFactor) without a list of
// systems: what is system-specific stays in the plugin's file.
//
// The Jacobian columns: a system perturbs its states in its own way (VINS-Fusion's
// PoseLocalParameterization, Basalt's applyInc, OKVIS's PoseManifold, g2o's VertexPose). Where
// that perturbation agrees, to first order at every state, with a registered state convention,
// the plugin names that convention and, for each 3-block of its tangent, the matrix output and
// column that hold the derivative by it. The host assembles the residual's Jacobian in that
// convention's chart and carries it to any other with the registry's conversion Jacobians
// (J_sys J_{sys<-ref}(x), the note's chain rule of section 2.2). First order is all a
// Jacobian sees: J_{sys<-ref}(x) is d local_sys(x, retract_ref(x, d)) / d d at d = 0.
#pragma once

#include "imuconv/block_order.h"

namespace imuconv {

/// Three columns of a Jacobian the factor writes, and the state tangent block they
/// differentiate by.
struct ResidualJacobianColumns {
  /// The matrix output's path: its name, prefixed by the groups it is written in and '/'
  /// ("raw/jacobian_pose_i"); nullptr marks an unused entry.
  const char* matrix = nullptr;
  /// Its columns [first_column, first_column + 3).
  int first_column = 0;
  /// The block of ResidualCostSpec::state_convention's tangent they differentiate by.
  Block block = Block::p;
};

/// How the system's solver weights the residual r (n = degrees_of_freedom()).
enum class ResidualWeighting : int {
  /// `weighting_matrix` names an n x n matrix W; the whitened residual is W r.
  SqrtInformation = 1,
  /// `weighting_matrix` names an n x n symmetric positive semi-definite information I; the
  /// whitened residual is S r for a square root S^T S = I (the cost r^T I r does not depend on
  /// which one).
  Information = 2,
  /// The measurement's covariance as evaluate() receives it (in increment_convention()), its
  /// leading n x n block C (the residual's rows are its first n, in its order); the whitened
  /// residual is S r with S^T S = C^-1.
  MeasurementCovariance = 3,
};

/// Up to five 3-blocks per state: the whole 15-dimensional tangent. A block not listed is
/// one the residual does not depend on (a zero Jacobian): e.g. the end state's biases for a
/// 9-dimensional residual without bias-walk rows.
inline constexpr int kResidualJacobianBlocks = 5;

/// A residual plugin's cost: evaluate() must write every output named here, with
/// degrees_of_freedom() rows, whenever it returns Ok for a measurement with a weighting.
struct ResidualCostSpec {
  /// The vector output that is the system's residual, before weighting ("raw/residual").
  const char* residual = nullptr;
  /// A registered state convention whose perturbation of a state is, to first order, the one
  /// the system's Jacobians are taken in (its id, e.g. "left").
  const char* state_convention = nullptr;
  ResidualWeighting weighting = ResidualWeighting::SqrtInformation;
  /// The matrix output for SqrtInformation and Information; nullptr for MeasurementCovariance.
  const char* weighting_matrix = nullptr;
  /// The derivatives by the start state x_s and by the end state x_e.
  ResidualJacobianColumns start[kResidualJacobianBlocks];
  ResidualJacobianColumns end[kResidualJacobianBlocks];
};

}  // namespace imuconv
