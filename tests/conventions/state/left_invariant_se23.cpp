// `left_invariant_se23`: the generic suite and its conversion from `left` derived by hand.
#include "../convention_suite.h"

IMUCONV_STATE_CONVENTION(left_invariant_se23, "theta v p bg ba");

TEST(StateStructure, LeftToLeftInvariant) {
  // X^ Exp(xi) at first order: R^ phi, R^ nu, R^ rho.
  ExpectConversion("left", "left_invariant_se23", [](const ImuState& x) -> BlockEntries {
    const Mat3 Rt = x.R.transpose();
    return {{"theta", Rt}, {"v", Rt}, {"p", Rt}};
  });
}
