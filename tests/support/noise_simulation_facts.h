// What a built-in scheme says of its noise (noise_simulation(), core/include/imuconv/
// noise_simulation.h), which imuconv montecarlo simulates without naming any method: the cells
// and readings of docs/montecarlo.md's lists and table, declared in each system's own test file
// (declared_facts.h), one line per plugin id:
//   IMUCONV_NOISE_SIMULATION(Propagator, okvis2, kCentered, kContinuous, true);
// (or with its increment_mean() fact, IMUCONV_SCHEME_FACTS, scheme_fact_declarations.h)
// in tests/integrators/ for a propagator, tests/preintegrators/ for a preintegrator. The cells
// follow from each scheme's arithmetic (docs/noise.md): a held sample's cell is the step it is
// held over; a scheme averaging a step's two ends or interpolating between knots weighs each
// sample over half of each step beside it. CheckDeclaredNoiseSimulations, run once by each of
// the two areas (noise_simulation.cpp there), compares every declaration with its plugin and
// fails for a plugin of the kind loaded from the built-in directory without one.
#pragma once

#include <gtest/gtest.h>

#include <string>

#include "declared_facts.h"
#include "imuconv/noise_simulation.h"
#include "imuconv_test.h"
#include "scheme_facts.h"

namespace imuconv::test {

/// The facts a test states of a scheme's noise_simulation() (its note is the plugin's own
/// sentence: only required to be there).
struct NoiseSimulationFacts {
  SampleCells cells;
  NoiseReading reading;
  bool simulable;
};
template <PluginKind kKind>
struct NoiseSimulationOf {
  using Facts = NoiseSimulationFacts;
  static constexpr const char* kWhat = "noise simulation (cells, reading, simulable)";
};

template <PluginKind kKind>
void CheckDeclaredNoiseSimulations(const char* where) {
  CheckSchemeDeclarations<NoiseSimulationOf, kKind>(
      where, "IMUCONV_NOISE_SIMULATION", "<cells>, <reading>, <simulable>",
      [](const std::string& id, const NoiseSimulationFacts& facts) {
        const NoiseSimulation sim = SchemePlugin<kKind>(id)->noise_simulation();
        EXPECT_EQ(sim.cells, facts.cells) << id;
        EXPECT_EQ(sim.reading, facts.reading) << id;
        EXPECT_EQ(sim.simulable, facts.simulable) << id;
        ASSERT_NE(sim.note, nullptr) << id;
      });
}

}  // namespace imuconv::test

/// Declares what the plugin ID of kind KIND (Propagator or Preintegrator) says of its noise:
/// CELLS a SampleCells and READING a NoiseReading enumerator (kCentered, kContinuous, ...),
/// SIMULABLE true or false.
#define IMUCONV_NOISE_SIMULATION(KIND, ID, CELLS, READING, SIMULABLE)                            \
  [[maybe_unused]] static const bool KIND##_##ID##_noise_simulation_declared = ::imuconv::test:: \
      DeclaredFacts<::imuconv::test::NoiseSimulationOf<::imuconv::PluginKind::KIND>>::Add(       \
          #ID, {::imuconv::SampleCells::CELLS, ::imuconv::NoiseReading::READING, SIMULABLE},     \
          {__FILE__, __LINE__})
