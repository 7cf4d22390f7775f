// The `orb_slam3` preintegrator's facts that live with the preintegrators (its numbers against
// ORB-SLAM3's own are tested in tests/reference/orb_slam3_plugin.cpp and orb_slam3_anchor.cpp,
// its EdgeInertial Jacobians in tests/integrators/orb_slam3.cpp).
#include "scheme_fact_declarations.h"

namespace {

// Its noise and mean (scheme_fact_declarations.h; docs/montecarlo.md, docs/orb-slam3.md): the
// tracker's feeding averages consecutive samples (centered cells), and IMU::Preintegrated keeps
// the bias constant over the interval, its C having the walk on the bias blocks only. No mean
// alone (docs/orb-slam3.md): each trial runs the full float preintegration.
IMUCONV_SCHEME_FACTS(Preintegrator, orb_slam3, kCentered, kWalkInIncrementOnly, true, kNotProvided);

}  // namespace
