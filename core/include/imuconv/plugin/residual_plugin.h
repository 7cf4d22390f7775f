// What a residual plugin (residual_factor.h) is made of when its arithmetic is a kernel of
// imuconv_core: a struct naming the increment convention its measurement is expressed in, its
// layout text and degrees of freedom, and the evaluation, which adapts the measurement and
// the states to the kernel's types and writes the kernel's outputs to the sink:
//
//   struct MyFactor {
//     static constexpr const char* kIncrementConvention = "my_system";
//     static constexpr const char* kLayout = "MySystem::Factor: residual [p, theta, v] ...";
//     static constexpr int kDegreesOfFreedom = 9;
//     imuconv::Status operator()(const imuconv::Preintegrated& m, const imuconv::ImuState& x_s,
//                                const imuconv::ImuState& x_e, const imuconv::Vec3& gravity,
//                                imuconv::ResidualSink& sink) const;
//   };
//   IMUCONV_PLUGIN(Residual, imuconv::plugin::KernelResidual<MyFactor>, "my_system", "1.0.0",
//                  "one line summary")
// The id comes from the IMUCONV_PLUGIN line. A struct that also declares
//     static constexpr imuconv::ResidualCostSpec kCostSpec{...};
// (residual_cost_spec.h) gives it as cost_spec(), so that its factor can be a Ceres cost.
#pragma once

#include <exception>
#include <string>
#include <type_traits>

#include "imuconv/residual_factor.h"

namespace imuconv::plugin {

namespace detail {
template <class Kernel, class = void>
struct HasCostSpec : std::false_type {};
template <class Kernel>
struct HasCostSpec<Kernel, std::void_t<decltype(&Kernel::kCostSpec)>> : std::true_type {};
}  // namespace detail

template <class Kernel>
class KernelResidual : public ResidualFactor {
 public:
  const char* increment_convention() const noexcept override {
    return Kernel::kIncrementConvention;
  }
  const char* layout() const noexcept override { return Kernel::kLayout; }
  int degrees_of_freedom() const noexcept override { return Kernel::kDegreesOfFreedom; }
  const ResidualCostSpec* cost_spec() const noexcept override {
    if constexpr (detail::HasCostSpec<Kernel>::value)
      return &Kernel::kCostSpec;
    else
      return nullptr;
  }
  /// Runs the kernel so that no exception crosses the plugin boundary (kernels report bad
  /// input by Status; only std::bad_alloc while building a message can be thrown here).
  Status evaluate(const Preintegrated& m, const ImuState& x_s, const ImuState& x_e,
                  const Vec3& gravity, ResidualSink& sink) const noexcept override {
    try {
      return Kernel{}(m, x_s, x_e, gravity, sink);
    } catch (const std::exception& e) {
      return Status::Error(std::string(id()) + ": " + e.what());
    }
  }
};

/// A system's pose-and-velocity state from a state, for a kernel whose state struct has members
/// R, p and v meaning what an ImuState's do (rotation, position and velocity, in the same world
/// frame) and takes the biases apart: Basalt's PoseVelState, ORB-SLAM3's pose with its velocity.
template <class PoseVel>
PoseVel PoseVelOf(const ImuState& x) {
  PoseVel s;
  s.R = x.R;
  s.p = x.p;
  s.v = x.v;
  return s;
}

}  // namespace imuconv::plugin
