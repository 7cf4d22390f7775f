// The IMU samples and noise densities of a reference case file (the format of
// tests/data/reference/cases/*.json, FORMAT.md), the input `imuconv check` propagates over.
// apps/refcase reads the same file for its own purpose (and its reader is private to it); this
// reads only the keys check needs, with the pipeline's checker, so every problem is reported
// with the file and its JSON pointer.
#pragma once

#include <string>
#include <vector>

#include "imuconv/types.h"

namespace imuconv::check {

struct CaseInput {
  std::vector<ImuSample> samples;             // strictly increasing times, seconds
  ImuNoise noise;                             // continuous-time densities (FORMAT.md)
  std::string source = "the case's samples";  // for messages: where the samples came from
};

/// Throws pipeline::ConfigError naming the file and each pointer (a missing or malformed
/// /imu row, non-increasing times, a gap or an implausible rate (the timing rules of
/// `imuconv run`), a negative or non-finite density, an unknown key), and
/// pipeline::ReadError when the file cannot be read.
CaseInput ReadCaseFile(const std::string& path);

}  // namespace imuconv::check
