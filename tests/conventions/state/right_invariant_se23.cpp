// `right_invariant_se23`: the generic suite and its conversions derived by hand (the SE_2(3)
// adjoint).
#include "suite.h"

namespace {

using namespace imuconv::test::state;

IMUCONV_CONVENTION_SUITE(StateConventionSuite, right_invariant_se23);

TEST(StateStructure, LeftToRightInvariantCouplesRotationIntoTranslations) {
  for (const ImuState& x : StateKind::Points()) {
    // Exp(phi) v^ + Jl(phi) nu = v^ + dv_l  =>  nu = dv_l - [phi]x v^ = dv_l + [v^]x dtheta_l.
    ExpectConversion("left", "right_invariant_se23", x,
                     Expect("left", "right_invariant_se23")
                         .set("theta", "theta", I3)
                         .set("v", "theta", so3::skew(x.v))
                         .set("v", "v", I3)
                         .set("p", "theta", so3::skew(x.p))
                         .set("p", "p", I3)
                         .set("bg", "bg", I3)
                         .set("ba", "ba", I3)
                         .matrix());
  }
}

TEST(StateStructure, LeftToRightInvariantIsTheSe23Adjoint) {
  for (const ImuState& x : StateKind::Points()) {
    // X Exp(xi) = Exp(Ad_X xi) X with Ad_X = [[R, 0, 0], [[v]x R, R, 0], [[p]x R, 0, R]] in
    // the order [phi, nu, rho]; biases are outside the group.
    const Mat3& R = x.R;
    ExpectConversion("left_invariant_se23", "right_invariant_se23", x,
                     Expect("left_invariant_se23", "right_invariant_se23")
                         .set("theta", "theta", R)
                         .set("v", "theta", so3::skew(x.v) * R)
                         .set("v", "v", R)
                         .set("p", "theta", so3::skew(x.p) * R)
                         .set("p", "p", R)
                         .set("bg", "bg", I3)
                         .set("ba", "ba", I3)
                         .matrix());
  }
}

}  // namespace
