// The propagators' noise facts (noise_simulation_facts.h), each declared in its system's own
// test file here: every declaration is what its plugin says, and every propagator loaded from
// the built-in plugin directory has one.
#include <gtest/gtest.h>

#include "noise_simulation_facts.h"

namespace {

TEST(PropagatorNoiseSimulation, EveryBuiltInSaysTheDeclaredCellsAndReading) {
  imuconv::test::CheckDeclaredNoiseSimulations<imuconv::PluginKind::Propagator>(
      "the propagator's own test file in tests/integrators/");
}

}  // namespace
