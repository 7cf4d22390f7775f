// What imuconv montecarlo makes of a plugin's noise_simulation() (core/include/imuconv/
// noise_simulation.h), which it simulates without naming any method: the model's name in the
// output, the mismatch flag and the note, and a hostile plugin's values outside the enums.
#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "imuconv_test.h"
#include "montecarlo.h"

namespace imuconv::montecarlo {
namespace {

using test::Plugins;

// What each built-in plugin says of its noise (its cells, reading and whether it is simulable)
// is declared in that system's own test file and checked there (tests/support/
// noise_simulation_facts.h, run by tests/integrators/noise_simulation.cpp and
// tests/preintegrators/noise_simulation.cpp); here, what montecarlo makes of it.

// montecarlo's model follows the plugin: the reading's name in the output, the mismatch flag,
// and the plugin's note (which says where its reading is documented).
TEST(MontecarloNoiseSimulation, TheModelIsThePluginsReading) {
  // One row a plugin: the model montecarlo simulates for it, whether that is the plugin's own
  // reading, and a part of the note it must say (nullptr: the note is not examined).
  struct ExpectedModel {
    PluginKind kind;
    const char* id;
    const char* simulated;
    bool matches;
    const char* note_mentions;
  };
  const ExpectedModel expected_models[] = {
      {PluginKind::Preintegrator, "basalt", "basalt", true, "docs/basalt.md"},
      {PluginKind::Preintegrator, "basalt_as_configured", "basalt_per_sample", true, nullptr},
      {PluginKind::Preintegrator, "vins_fusion_as_configured", "continuous", false, "MISMATCH"},
      {PluginKind::Propagator, "rk4", "continuous", true, nullptr}};
  for (const ExpectedModel& e : expected_models) {
    SCOPED_TRACE(e.id);
    const NoiseModel m = NoiseModelFor(ResolvePreintegrationMethod(Plugins(), e.kind, e.id));
    EXPECT_EQ(m.simulated, e.simulated);
    EXPECT_EQ(m.matches, e.matches);
    if (e.note_mentions != nullptr) {
      EXPECT_NE(m.note.find(e.note_mentions), std::string::npos) << m.note;
    }
  }
}

// Values outside the enums (a plugin built against another header) are hostile input: simulated
// as the defaults, and said as a mismatch rather than taken silently.
TEST(MontecarloNoiseSimulation, AnUnknownCellOrReadingIsSaidAsAMismatch) {
  struct Bogus final : Propagator {
    const char* id() const noexcept override { return "bogus"; }
    const char* native_convention() const noexcept override { return "left"; }
    Status propagate(const PropagationInput&, PropagationResult&) const noexcept override {
      return Status::Ok();
    }
    NoiseSimulation noise_simulation() const noexcept override {
      NoiseSimulation sim;
      sim.cells = static_cast<SampleCells>(7);
      sim.note = nullptr;  // also hostile: no note at all
      return sim;
    }
  };
  PreintegrationMethod method;
  method.id = "bogus";
  method.kind = PluginKind::Propagator;
  method.propagator = std::make_shared<Bogus>();
  const NoiseModel m = NoiseModelFor(method);
  EXPECT_EQ(m.simulated, "continuous");
  EXPECT_FALSE(m.matches);
  EXPECT_NE(m.note.find("cells 7"), std::string::npos) << m.note;
}

}  // namespace
}  // namespace imuconv::montecarlo
