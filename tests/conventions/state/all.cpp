// State (error-state) conventions as a kind: the generic suite's tests (instantiated once per
// convention, in that convention's file), every ordered pair through the registry, and the
// block orders.
#include "../convention_suite.h"

IMUCONV_DEFINE_CONVENTION_SUITE(StateConventionSuite, imuconv::test::StateKind);

namespace {

// The seven built-in conventions and the reference, each in the block order it documents.
TEST(StateConventions, BuiltInsAndTheirBlockOrders) {
  imuconv::test::CheckBuiltInBlockOrders<imuconv::test::StateKind>(
      {{"left", "p theta v bg ba"},
       {"gtsam_navstate", "theta p v ba bg"},
       {"gtsam_pose3_vel", "theta p v ba bg"},
       {"forster", "theta p v bg ba"},
       {"fast_lio2", "p theta v bg ba"},
       {"openvins_jpl", "theta p v bg ba"},
       {"right_invariant_se23", "theta v p bg ba"},
       {"left_invariant_se23", "theta v p bg ba"},
       {"okvis2", "p theta v bg ba"}});
}

}  // namespace
