// `left`: the paper's left error state (eq. left-dpr..left-dba), the reference chart for
// state conventions: p = p^ + dp, R = Exp(dtheta) R^, v = v^ + dv, b = b^ + db;
// order [p, theta, v, bg, ba]. Used by the paper's propagation and by OKVIS-style filters.
#include "imuconv/plugin/convention.h"
#include "imuconv/plugin_abi.h"

namespace {

using imuconv::ImuState;
using imuconv::Mat15;
using imuconv::Vec15;

class Left : public imuconv::plugin::StateChart<imuconv::kLeftOrder> {
 public:
  void retract(const ImuState& x, const Vec15& d, ImuState& y) const noexcept override {
    imuconv::LeftRetract(x, d, y);
  }
  void local(const ImuState& x, const ImuState& y, Vec15& d) const noexcept override {
    imuconv::LeftLocal(x, y, d);
  }
  // The reference chart itself: both Jacobians are the identity.
  bool J_ref_this(const ImuState&, Mat15& J) const noexcept override { return RefThis(J, {}); }
  bool J_this_ref(const ImuState&, Mat15& J) const noexcept override { return ThisRef(J, {}); }
};

}  // namespace

IMUCONV_PLUGIN(StateConvention, Left, "left", "1.0.0",
               "paper's left error state: p+dp, Exp(dtheta)R, v+dv, b+db")
