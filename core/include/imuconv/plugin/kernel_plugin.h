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
//
// A kernel that is a template instance of the core (kernels/fast_lio2.h, okvis2_scheme.h, ...)
// is registered in one line, written in place: IMUCONV_KERNEL_PROPAGATOR or
// IMUCONV_KERNEL_PREINTEGRATOR (plugin/kernel_registration.h).
//
// The optional capabilities are given once here, from what the kernel struct declares:
//   static Status Mean(const PreintegrationInput&, PreintIncrement&)   the increment alone
//     (increment_mean(), increment_mean.h): where the kernel has a mean-only function
//     (kernels/mean_only.h); without it the plugin says "not provided";
//   static constexpr NoiseSimulation kNoiseSimulation   its sample cells and noise reading
//     (noise_simulation(), noise_simulation.h); without it the default (forward, continuous).
// A plugin whose kernel is a type of the core declares them on a struct derived from it.
#pragma once

#include <exception>
#include <string>
#include <type_traits>

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

/// Runs Kernel::Mean so that no exception crosses the plugin boundary.
template <class Kernel>
Status MeanContained(const char* id, const PreintegrationInput& in,
                     PreintIncrement& delta) noexcept {
  try {
    return Kernel::Mean(in, delta);
  } catch (const std::exception& e) {
    return Status::Error(std::string(id) + ": " + e.what());
  }
}

/// Whether the kernel struct declares Member<Kernel> (the detection idiom): each optional
/// capability below is one such member, used where it is there and defaulted where not.
template <template <class> class Member, class Kernel, class = void>
struct Declares : std::false_type {};
template <template <class> class Member, class Kernel>
struct Declares<Member, Kernel, std::void_t<Member<Kernel>>> : std::true_type {};

template <class Kernel>
using MeanMember = decltype(Kernel::Mean(std::declval<const PreintegrationInput&>(),
                                         std::declval<PreintIncrement&>()));
template <class Kernel>
using NativeConventionMember = decltype(Kernel::kNativeConvention);
template <class Kernel>
using NoiseSimulationMember = decltype(Kernel::kNoiseSimulation);

/// The kernel's native state convention: Kernel::kNativeConvention where it says one, `left`
/// (the convention of the core's own propagation kernels) where it does not.
template <class Kernel>
constexpr const char* NativeConventionOf() noexcept {
  if constexpr (Declares<NativeConventionMember, Kernel>::value)
    return Kernel::kNativeConvention;
  else
    return "left";
}

template <class Kernel>
NoiseSimulation NoiseSimulationOf() noexcept {
  if constexpr (Declares<NoiseSimulationMember, Kernel>::value)
    return Kernel::kNoiseSimulation;
  else
    return NoiseSimulation();
}

template <class Kernel>
Status IncrementMeanOf(const char* id, const PreintegrationInput& in,
                       PreintIncrement& delta) noexcept {
  if constexpr (Declares<MeanMember, Kernel>::value) {
    return MeanContained<Kernel>(id, in, delta);
  } else {
    (void)id;
    (void)in;
    delta = PreintIncrement();
    return IncrementMeanNotProvided();
  }
}

/// A propagator's or a preintegrator's (Base's) optional capabilities, increment_mean() and
/// noise_simulation(), from what Kernel declares: written once for both kinds. It adds no
/// virtual function, so Base's layout (the plugin ABI) is that of the kind.
template <class Kernel, class Base>
class KernelCapabilities : public Base {
 public:
  Status increment_mean(const PreintegrationInput& in,
                        PreintIncrement& delta) const noexcept override {
    return IncrementMeanOf<Kernel>(this->id(), in, delta);
  }
  NoiseSimulation noise_simulation() const noexcept override { return NoiseSimulationOf<Kernel>(); }
};

}  // namespace detail

/// A propagator whose propagate() is Kernel{}(in, out), in the native convention
/// Kernel::kNativeConvention (`left` when the kernel names none).
template <class Kernel>
class KernelPropagator : public detail::KernelCapabilities<Kernel, Propagator> {
 public:
  const char* native_convention() const noexcept override {
    return detail::NativeConventionOf<Kernel>();
  }
  Status propagate(const PropagationInput& in, PropagationResult& out) const noexcept override {
    return detail::RunContained<Kernel>(this->id(), in, out);
  }
};

/// A preintegrator whose integrate() is Kernel{}(in, out), with its covariance in
/// Kernel::kCovConvention and its bias Jacobian in Kernel::kJacobianConvention.
template <class Kernel>
class KernelPreintegrator : public detail::KernelCapabilities<Kernel, Preintegrator> {
 public:
  const char* cov_convention() const noexcept override { return Kernel::kCovConvention; }
  const char* jacobian_convention() const noexcept override { return Kernel::kJacobianConvention; }
  Status integrate(const PreintegrationInput& in, Preintegrated& out) const noexcept override {
    return detail::RunContained<Kernel>(this->id(), in, out);
  }
};

}  // namespace imuconv::plugin
