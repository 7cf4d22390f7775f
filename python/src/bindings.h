// The module's parts, one file each: values (state.cpp), the registry (registry.cpp), the
// bridge between preintegration and propagation (bridge.cpp), pipelines (pipeline.cpp).
#pragma once

#include <pybind11/pybind11.h>

#include <string>
#include <vector>

#include "imuconv/bridge.h"
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

/// A measurement in a named convention, with that convention's block order and the row and
/// column blocks of its J_bias (in its jacobian_convention's order).
struct Expressed : Preintegrated {
  std::vector<std::string> blocks;
  std::vector<std::string> J_bias_rows, J_bias_columns;
};

/// For the reprs: "[0.1, -2, 3]", "['theta', 'p']", and an increment as "rotation 2.5 deg about
/// [..], dp=[..], dv=[..]" (with dbg, dba when not zero).
std::string VecText(const Vec3& v);
std::string Labels(const std::vector<std::string>& labels);
std::string IncrementText(const PreintIncrement& d);

void BindValues(py::module_& m);
void BindRegistry(py::module_& m);
void BindBridge(py::module_& m);
void BindPipeline(py::module_& m);
void BindMeasurements(py::module_& m);
/// imuconv.optimize: only with Ceres (IMUCONV_HAVE_OPTIMIZE).
void BindOptimize(py::module_& m);

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

/// For a catch block after blocking work done without the GIL: a Ctrl-C that arrived meanwhile
/// ended a blocked open or read with EINTR, which the library reports as an Error ("cannot open
/// it for writing: Interrupted system call"); the interrupt is what happened, so it is raised
/// (KeyboardInterrupt) instead of that error. Otherwise returns and the caller rethrows.
inline void RaiseIfInterrupted() {
  if (PyErr_CheckSignals() != 0) throw py::error_already_set();
}

/// A path argument, the same in every call that takes one: str, bytes or os.PathLike
/// (whose __fspath__ gives str or bytes), as the file system's bytes (os.fsencode). Anything
/// else, or a NUL inside, is a ValueError naming `name`.
bool IsPathArgument(py::handle h);
std::string PathArgument(py::handle h, const char* name);

/// Samples that look mistaken (gyro and accelerometer columns swapped, g, deg/s:
/// pipeline::ImuPlausibilityWarnings) give a UserWarning each, as the CLI warns wherever it
/// reads an IMU file; the call goes on (the numbers may be meant).
void WarnIfImplausible(const std::vector<ImuSample>& samples);

}  // namespace imuconv::python
