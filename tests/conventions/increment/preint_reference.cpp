// `preint_reference`, the increment reference chart (built in): the generic suite.
#include "../convention_suite.h"

IMUCONV_CONVENTION_SUITE(IncrementConventionSuite, preint_reference);
IMUCONV_CONVENTION_BLOCK_ORDER(IncrementKind, preint_reference, "theta p v bg ba");
IMUCONV_BIAS_JACOBIAN_CHART(preint_reference, "preint_reference");
