// The `okvis2` preintegrator's facts that live with the preintegrators (its numbers against
// OKVIS2's own are tested in tests/reference/okvis2_anchor.cpp and okvis2_plugins_anchor.cpp,
// its Jacobians in tests/integrators/okvis2.cpp).
#include "scheme_fact_declarations.h"

namespace {

// Its noise and mean (scheme_fact_declarations.h; docs/montecarlo.md, docs/okvis2.md):
// ImuError's trapezoidal loop averages a step's two ends (centered cells); sigma_*_c are
// densities. No mean alone (docs/okvis2.md): each trial runs the full preintegration.
IMUCONV_SCHEME_FACTS(Preintegrator, okvis2, kCentered, kContinuous, true, kNotProvided);

}  // namespace
