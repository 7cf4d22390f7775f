// `preint_reference`, the increment reference chart (built in): the generic suite.
#include "../convention_suite.h"

IMUCONV_CONVENTION_SUITE(IncrementConventionSuite, preint_reference);
