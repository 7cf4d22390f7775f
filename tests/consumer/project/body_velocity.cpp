// A user's convention with no analytic Jacobians: R = R^ Exp(dtheta), p = p^ + dp,
// v = v^ + R^ dv (velocity error in the body frame), biases additive; [theta, p, v, bg, ba].
// The registry derives its conversions numerically. Its id is declared once, on the
// IMUCONV_PLUGIN line.
#include <imuconv/plugin_abi.h>
#include <imuconv/so3.h>

namespace {
using namespace imuconv;
class BodyVelocity : public StateConvention {
 public:
  BlockOrder order() const noexcept override {
    return {Block::theta, Block::p, Block::v, Block::bg, Block::ba};
  }
  void retract(const ImuState& x, const Vec15& d, ImuState& y) const noexcept override {
    y.R = x.R * so3::Exp(d.segment<3>(0));
    y.p = x.p + d.segment<3>(3);
    y.v = x.v + x.R * d.segment<3>(6);
    y.bg = x.bg + d.segment<3>(9);
    y.ba = x.ba + d.segment<3>(12);
  }
  void local(const ImuState& x, const ImuState& y, Vec15& d) const noexcept override {
    d << so3::Log(x.R.transpose() * y.R), y.p - x.p, x.R.transpose() * (y.v - x.v), y.bg - x.bg,
        y.ba - x.ba;
  }
};
}  // namespace
IMUCONV_PLUGIN(StateConvention, BodyVelocity, "body_velocity", "1.0.0",
               "consumer test: velocity error in body frame")
