// What a propagator or preintegrator plugin is made of when its numerics are a kernel of
// imuconv_core (the hot loop is compiled there and called once per interval, never through
// the plugin per sample): the plugin file names the kernel and, for a preintegrator, the two
// conventions its outputs are in; the id comes from its IMUCONV_PLUGIN line.
//
//   struct Euler {
//     imuconv::Status operator()(const imuconv::PropagationInput& in, imuconv::PropagationResult&
//     out) const {
//       return imuconv::kernels::PropagateHeld<imuconv::kernels::Hold::Euler>(in, out);
//     }
//   };
//   IMUCONV_PLUGIN(Propagator, imuconv::plugin::KernelPropagator<Euler>, "euler", "1.0.0", "...")
#pragma once

#include <exception>
#include <string>

#include "imuconv/preintegrator.h"
#include "imuconv/propagator.h"

namespace imuconv::plugin {

namespace detail {
/// Runs a kernel so that no exception crosses the plugin boundary. Kernels report bad input
/// by Status; only std::bad_alloc while building that message can be thrown here.
template <class Kernel, class In, class Out>
Status RunContained(const char* id, const In& in, Out& out) noexcept {
  try {
    return Kernel{}(in, out);
  } catch (const std::exception& e) {
    return Status::Error(std::string(id) + ": " + e.what());
  }
}
}  // namespace detail

/// A propagator whose propagate() is Kernel{}(in, out), in the native convention `left`.
template <class Kernel>
class KernelPropagator : public Propagator {
 public:
  const char* native_convention() const noexcept override { return "left"; }
  Status propagate(const PropagationInput& in, PropagationResult& out) const noexcept override {
    return detail::RunContained<Kernel>(id(), in, out);
  }
};

/// A preintegrator whose integrate() is Kernel{}(in, out), with its covariance in
/// Kernel::kCovConvention and its bias Jacobian in Kernel::kJacobianConvention.
template <class Kernel>
class KernelPreintegrator : public Preintegrator {
 public:
  const char* cov_convention() const noexcept override { return Kernel::kCovConvention; }
  const char* jacobian_convention() const noexcept override { return Kernel::kJacobianConvention; }
  Status integrate(const PreintegrationInput& in, Preintegrated& out) const noexcept override {
    return detail::RunContained<Kernel>(id(), in, out);
  }
};

}  // namespace imuconv::plugin
