// `left_invariant_se23`: the generic suite and its conversion from `left` derived by hand.
#include "suite.h"

namespace {

using namespace imuconv::test::state;

IMUCONV_CONVENTION_SUITE(StateConventionSuite, left_invariant_se23);

TEST(StateStructure, LeftToLeftInvariant) {
  for (const ImuState& x : StateKind::Points()) {
    const Mat3 Rt = x.R.transpose();
    // X^ Exp(xi) at first order: R^ phi, R^ nu, R^ rho.
    ExpectConversion("left", "left_invariant_se23", x,
                     Expect("left", "left_invariant_se23")
                         .set("theta", "theta", Rt)
                         .set("v", "v", Rt)
                         .set("p", "p", Rt)
                         .set("bg", "bg", I3)
                         .set("ba", "ba", I3)
                         .matrix());
  }
}

}  // namespace
