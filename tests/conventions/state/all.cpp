// State (error-state) conventions as a kind: the generic suite's tests (instantiated once per
// convention, in that convention's file), every ordered pair through the registry, and the
// block orders.
#include "../convention_suite.h"

IMUCONV_DEFINE_CONVENTION_SUITE(StateConventionSuite, imuconv::test::StateKind);

namespace {

// Each convention declares the block order it documents in its own test file
// (IMUCONV_CONVENTION_BLOCK_ORDER, state/<id>.cpp): the loaded plugins agree with every
// declaration, and every state convention loaded from the built-in plugin directory has one.
TEST(StateConventions, BuiltInsAndTheirBlockOrders) {
  imuconv::test::CheckDeclaredBlockOrders<imuconv::test::StateKind>(
      "its own test file, tests/conventions/state/<id>.cpp");
}

}  // namespace
