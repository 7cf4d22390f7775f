// The mean alone of the core's integration kernels, for re-integrations that need the end
// value and nothing else (imuconv montecarlo's trials: the predicted covariance is computed
// once, each noisy trial only integrates its samples, docs/montecarlo.md).
//
// Each function below gives, bit for bit, the increment that the kernel's full run gives
// through its plugin and the bridge (registry/src/bridge.cpp), without the transition matrix,
// the covariance or (for the propagators) the plugin call:
//   propagators (euler, midpoint, rk4), preintegration by propagation (the paper, section
//     3.1): propagated from the identity with zero gravity, the end state is the increment;
//   native preintegrators (manifold, tangent): their increment, which the bridge copies
//     unchanged into preint_reference (only the covariance and bias Jacobian change chart).
// tests/integrators/mean_only.cpp compares each with the full path bit for bit.
//
// Why the same arithmetic: every method here runs a kernel compiled once, in imuconv_core
// (core/src/kernels/), through the instance the CPU runs; its plugin calls the same copy.
// rk4's state-only mode is the same compiled function as the plugin's full run, and its state
// is the same IEEE operations in every output mode (core/src/kernels/rk4_window.h,
// "Instances"). The held propagators and the native preintegrators run the preintegration
// kernel's recursion with its covariance switched off, which the test checks to round the same
// way on this build and CPU.
#pragma once

#include "imuconv/kernels/euler.h"
#include "imuconv/kernels/preintegration.h"
#include "imuconv/kernels/rk4.h"

namespace imuconv::kernels {

/// The kernels with a mean-only path, named as their plugins' ids (plugins/propagators/,
/// plugins/preintegrators/).
enum class MeanKernel { kEuler, kMidpoint, kRk4, kManifold, kTangent };

namespace mean_only_detail {

/// A held-input propagation's end state: IntegrateHeld's route (the preintegration kernel's
/// instance for this CPU), its Phi and covariance left out.
template <Hold kHold>
inline void HeldEndState(const PropagationInput& in, ImuState& x_e) {
  StartFrameManifold pre;  // BestIsa() is available, so the kernel cannot refuse it
  (void)IntegrateManifoldStartFrame(held_detail::StartFrameInput(in), kHold, /*covariance=*/false,
                                    BestIsa(), pre);
  held_detail::ComposeEndState(in, pre.increment,
                               x_e);  // as IntegrateHeldByPreintegration composes it
}

}  // namespace mean_only_detail

/// The increment (dR, dp, dv; dbg = dba = 0) of `kernel` over `window` at the bias estimate
/// (bg, ba), as the method's full preintegration gives it (see the file comment). `noise` is
/// only checked (the mean does not depend on it). Checks the input as the full run does and
/// returns its error; never throws except std::bad_alloc while building a message.
inline Status IncrementMean(MeanKernel kernel, const SampleWindow& window, const Vec3& bg,
                            const Vec3& ba, const ImuNoise& noise, PreintIncrement& delta) {
  delta = PreintIncrement();
  if (kernel == MeanKernel::kManifold || kernel == MeanKernel::kTangent) {
    PreintegrationInput in;
    in.bg = bg;
    in.ba = ba;
    in.noise = noise;
    in.window = window;
    Preintegrated out;
    const Status st = kernel == MeanKernel::kManifold ? IntegrateManifold<false>(in, out)
                                                      : IntegrateTangent<false>(in, out);
    if (!st.ok()) return st;
    delta.dR = out.delta.dR;
    delta.dp = out.delta.dp;
    delta.dv = out.delta.dv;
    return st;
  }
  const PropagationInput in =
      PreintegrationByPropagationStart(window, bg, ba, noise);  // the bridge's start
  Status st = CheckPropagationInput(in);
  if (!st.ok()) return st;
  ImuState x_e;
  switch (kernel) {
    case MeanKernel::kEuler:
      mean_only_detail::HeldEndState<Hold::Euler>(in, x_e);
      break;
    case MeanKernel::kMidpoint:
      mean_only_detail::HeldEndState<Hold::Midpoint>(in, x_e);
      break;
    default: {
      PropagationResult r;
      IntegrateRk4Window(in, r, Outputs::State, 1,
                         Isa::kAuto);  // the plugin's one step per knot interval
      x_e = r.x_e;
    }
  }
  delta.dR = x_e.R;
  delta.dp = x_e.p;
  delta.dv = x_e.v;
  return st;
}

}  // namespace imuconv::kernels
