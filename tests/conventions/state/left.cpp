// `left`, the state reference chart: the generic suite (its Jacobians are the identity).
#include "../convention_suite.h"

IMUCONV_CONVENTION_SUITE(StateConventionSuite, left);
IMUCONV_CONVENTION_BLOCK_ORDER(StateKind, left, "p theta v bg ba");
