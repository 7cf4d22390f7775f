// What an output leaves out: the top-level "omit" list of a pipeline, also what the measurement
// writer takes (measurement.h).
#pragma once

namespace imuconv::pipeline {

/// What the output leaves out (the top-level "omit" list).
struct OmitSpec {
  bool Phi = false;        ///< transition matrices (propagate, propagate_by_preintegration steps)
  bool cov = false;        ///< covariances of measurements, propagations and steps
  bool J_bias = false;     ///< bias Jacobians of measurements
  bool R = false;          ///< rotation matrices of increments (q_wxyz stays)
  bool reference = false;  ///< a measurement's preint_reference J_bias and cov when it is expressed
                           ///< in other conventions
};

}  // namespace imuconv::pipeline
