// The checks a convention passes before the registry accepts it: its block order is a
// permutation of the five blocks, local inverts retract, and its analytic Jacobians (if any)
// agree with Ridders' differences against its kind's reference chart.
#pragma once

#include <string>

#include "imuconv/chart.h"

namespace imuconv::detail {

/// "" when the convention passes, else what failed. *analytic: it gives analytic Jacobians.
template <class Value>
std::string CheckConvention(const Chart<Value>& c, bool* analytic);

extern template std::string CheckConvention<ImuState>(const Chart<ImuState>&, bool*);
extern template std::string CheckConvention<PreintIncrement>(const Chart<PreintIncrement>&, bool*);

}  // namespace imuconv::detail
