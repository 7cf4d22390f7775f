// The `okvis2` preintegrator's facts that live with the preintegrators (its numbers against
// OKVIS2's own are tested in tests/reference/okvis2_anchor.cpp and okvis2_plugins_anchor.cpp,
// its Jacobians in tests/integrators/okvis2.cpp).
#include "increment_mean_facts.h"
#include "noise_simulation_facts.h"

namespace {

// Its noise (noise_simulation_facts.h; docs/montecarlo.md, docs/okvis2.md): ImuError's
// trapezoidal loop averages a step's two ends (centered cells); sigma_*_c are densities.
IMUCONV_NOISE_SIMULATION(Preintegrator, okvis2, kCentered, kContinuous, true);
// No mean alone (docs/okvis2.md): each trial runs the full preintegration.
IMUCONV_INCREMENT_MEAN(Preintegrator, okvis2, kNotProvided);

}  // namespace
