// Every fact a built-in scheme's own test file declares of it (a propagator's in
// tests/integrators/, a preintegrator's in tests/preintegrators/), in one line per plugin id:
//   IMUCONV_SCHEME_FACTS(Propagator, okvis2, kCentered, kContinuous, true, kNotProvided);
// its noise (cells, reading, simulable: noise_simulation_facts.h, docs/montecarlo.md) and
// whether it gives the mean alone (increment_mean_facts.h). The line is the two declarations
// those headers define, IMUCONV_NOISE_SIMULATION and IMUCONV_INCREMENT_MEAN, made at once, so
// that a system's facts stand together and each is still checked by its own shared test
// (noise_simulation.cpp, mean_only.cpp in each area); either may also be written alone.
#pragma once

#include "increment_mean_facts.h"
#include "noise_simulation_facts.h"

/// Declares what the plugin ID of kind KIND (Propagator or Preintegrator) says of its noise
/// (CELLS, READING, SIMULABLE as IMUCONV_NOISE_SIMULATION takes them) and whether it gives the
/// mean alone (MEAN, kProvided or kNotProvided, as IMUCONV_INCREMENT_MEAN takes it).
#define IMUCONV_SCHEME_FACTS(KIND, ID, CELLS, READING, SIMULABLE, MEAN) \
  IMUCONV_NOISE_SIMULATION(KIND, ID, CELLS, READING, SIMULABLE);        \
  IMUCONV_INCREMENT_MEAN(KIND, ID, MEAN)
