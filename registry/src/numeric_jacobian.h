// d local_to(x, retract_from(x, d)) / d d at d = 0 by Ridders' differences: a conversion
// factor for a chart that gives no analytic Jacobian, and the load-time check of one that
// does. Either side may be a Chart<Value> or the kind's ReferenceChart<Value>.
#pragma once

#include "imuconv/numeric.h"
#include "imuconv/types.h"

namespace imuconv::detail {

template <class From, class To, class Value>
Mat15 NumericJacobian(const From& from, const To& to, const Value& x) {
  return RiddersJacobian([&](const Vec15& d, Vec15& out) {
    Value y;
    from.retract(x, d, y);
    to.local(x, y, out);
  });
}

}  // namespace imuconv::detail
