// The module's parts, one file each: values (state.cpp), the registry (registry.cpp), the
// bridge between preintegration and propagation (bridge.cpp), pipelines (pipeline.cpp).
#pragma once

#include <pybind11/pybind11.h>

#include <vector>

#include "imuconv/registry.h"
#include "imuconv/types.h"

namespace imuconv::python {

namespace py = pybind11;

/// The Python Registry: a Registry and what failed to load into it.
struct LoadedRegistry : Registry {
  std::vector<LoadIssue> load_issues;
};

/// A 15x15 covariance argument: symmetric and positive semi-definite (core's
/// CovarianceProblem, the rule every pipeline input follows); nothing is repaired.
Mat15 CheckedCovariance(py::handle obj, const char* name);

void BindValues(py::module_& m);
void BindRegistry(py::module_& m);
void BindBridge(py::module_& m);
void BindPipeline(py::module_& m);

/// Noise densities from a mapping with exactly the four keys of a pipeline's "noise" form
/// (gyro_noise_density, accel_noise_density, gyro_random_walk, accel_random_walk): a missing
/// or unknown key, a negative or non-finite value is a ValueError naming it.
ImuNoise ReadNoise(py::handle noise);

/// IMU samples from an (N, 7) array of rows t, wx, wy, wz, ax, ay, az (seconds, rad/s, m/s^2),
/// as the reference case files hold them: N >= 2, and the pipeline's checks of every sample
/// series (imuconv/pipeline/sample_checks.h: finite, strictly increasing t, a plausible rate,
/// no gap beyond 10 x the median period unless allow_gaps), each a ValueError "samples: row k:
/// <the pipeline's sentence>".
std::vector<ImuSample> ReadSamples(py::handle samples, bool allow_gaps);

/// The noise must keep the covariance finite over these samples (FindNoiseIssue).
void RequireUsableNoise(const ImuNoise& noise, const std::vector<ImuSample>& samples);

}  // namespace imuconv::python
