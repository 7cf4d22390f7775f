// The preintegrators' noise facts (noise_simulation_facts.h), each declared in its system's own
// test file here: every declaration is what its plugin says, and every preintegrator loaded
// from the built-in plugin directory has one.
#include <gtest/gtest.h>

#include "noise_simulation_facts.h"

namespace {

TEST(PreintegratorNoiseSimulation, EveryBuiltInSaysTheDeclaredCellsAndReading) {
  imuconv::test::CheckDeclaredNoiseSimulations<imuconv::PluginKind::Preintegrator>(
      "the preintegrator's own test file in tests/preintegrators/");
}

}  // namespace
