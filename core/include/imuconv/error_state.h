// The names the conventions had before Chart<Value> (chart.h) served both kinds. Deprecated:
// use StateConvention and IncrementConvention; these aliases go with the final rename.
#pragma once

#include "imuconv/chart.h"

namespace imuconv {

using ErrorState = StateConvention;
using PreintConvention = IncrementConvention;

}  // namespace imuconv
