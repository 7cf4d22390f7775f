#include "builtin.h"

#include "imuconv/reference_charts.h"

namespace imuconv::detail {

void PreintReferenceConvention::retract(const PreintIncrement& x, const Vec15& d, PreintIncrement& y) const noexcept {
  PreintReferenceRetract(x, d, y);
}
void PreintReferenceConvention::local(const PreintIncrement& x, const PreintIncrement& y, Vec15& d) const noexcept {
  PreintReferenceLocal(x, y, d);
}

}  // namespace imuconv::detail
