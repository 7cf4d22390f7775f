// What `imuconv plugins --check` runs in its child process for each plugin file
// (plugin_check.cpp forks and supervises; this is the part that calls plugin code).
#pragma once

#include <string>

namespace imuconv::cli {

/// Loads `file` into a registry of its own and exercises what it provides: a propagator's
/// propagate() and a preintegrator's integrate() on a 10 ms test window, a residual's
/// evaluate() on a 10 ms test measurement, their outputs required finite; a convention's charts and
/// Jacobians by the registry's own load checks. Returns the "ok" description; throws imuconv::Error
/// saying what failed.
std::string ExercisePlugin(const std::string& file);

}  // namespace imuconv::cli
