// `preint_reference`, the increment reference chart (built in): the generic suite.
#include "../convention_suite.h"

IMUCONV_INCREMENT_CONVENTION(preint_reference, "theta p v bg ba", "preint_reference");
