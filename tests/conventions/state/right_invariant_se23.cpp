// `right_invariant_se23`: the generic suite and its conversions derived by hand (the SE_2(3)
// adjoint).
#include "../convention_suite.h"

IMUCONV_STATE_CONVENTION(right_invariant_se23, "theta v p bg ba");

TEST(StateStructure, LeftToRightInvariantCouplesRotationIntoTranslations) {
  // Exp(phi) v^ + Jl(phi) nu = v^ + dv_l  =>  nu = dv_l - [phi]x v^ = dv_l + [v^]x dtheta_l.
  ExpectConversion("left", "right_invariant_se23", [](const ImuState& x) -> BlockEntries {
    return {{"v", "theta", so3::skew(x.v)}, {"p", "theta", so3::skew(x.p)}};
  });
}

TEST(StateStructure, LeftToRightInvariantIsTheSe23Adjoint) {
  // X Exp(xi) = Exp(Ad_X xi) X with Ad_X = [[R, 0, 0], [[v]x R, R, 0], [[p]x R, 0, R]] in
  // the order [phi, nu, rho]; biases are outside the group.
  ExpectConversion("left_invariant_se23", "right_invariant_se23",
                   [](const ImuState& x) -> BlockEntries {
                     const Mat3& R = x.R;
                     return {{"theta", R},
                             {"v", "theta", so3::skew(x.v) * R},
                             {"v", R},
                             {"p", "theta", so3::skew(x.p) * R},
                             {"p", R}};
                   });
}
