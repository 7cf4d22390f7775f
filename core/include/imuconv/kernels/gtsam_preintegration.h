// The former name of the preintegration kernel's public header. Include
// imuconv/kernels/preintegration.h; this forward remains only until every includer has moved.
#pragma once

#include "imuconv/kernels/preintegration.h"
