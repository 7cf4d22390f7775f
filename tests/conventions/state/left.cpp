// `left`, the state reference chart: the generic suite (its Jacobians are the identity).
#include "../convention_suite.h"

IMUCONV_STATE_CONVENTION(left, "p theta v bg ba");
