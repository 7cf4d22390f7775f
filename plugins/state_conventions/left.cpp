// `left`: the paper's left error state (eq. left-dpr..left-dba), the reference chart for
// state conventions: p = p^ + dp, R = Exp(dtheta) R^, v = v^ + dv, b = b^ + db;
// order [p, theta, v, bg, ba]. Used by the paper's propagation and by OKVIS-style filters.
#include "imuconv/plugin_abi.h"
#include "imuconv/reference_charts.h"

namespace {

class Left final : public imuconv::ErrorState {
 public:
  const char* id() const noexcept override { return "left"; }
  imuconv::BlockLabels labels() const noexcept override { return {"p", "theta", "v", "bg", "ba"}; }
  void retract(const imuconv::ImuState& x, const imuconv::Vec15& d, imuconv::ImuState& y) const noexcept override {
    imuconv::LeftRetract(x, d, y);
  }
  void local(const imuconv::ImuState& x, const imuconv::ImuState& y, imuconv::Vec15& d) const noexcept override {
    imuconv::LeftLocal(x, y, d);
  }
  bool jacobian_to_reference(const imuconv::ImuState&, imuconv::Mat15& J) const noexcept override {
    J.setIdentity();
    return true;
  }
  bool jacobian_from_reference(const imuconv::ImuState&, imuconv::Mat15& J) const noexcept override {
    J.setIdentity();
    return true;
  }
};

}  // namespace

IMUCONV_PLUGIN(StateConvention, Left, "left", "1.0.0", "paper's left error state: p+dp, Exp(dtheta)R, v+dv, b+db")
