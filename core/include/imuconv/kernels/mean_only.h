// The mean alone of the core's integration kernels, for re-integrations that need the end
// value and nothing else (imuconv montecarlo's trials: the predicted covariance is computed
// once, each noisy trial only integrates its samples, docs/montecarlo.md). The kernels' plugins
// give it as their optional increment_mean() (increment_mean.h, plugin/kernel_plugin.h); no
// host calls these functions by a method's name.
//
// Each function below gives, bit for bit, the increment that the kernel's full run gives
// through its plugin and the bridge (registry/src/bridge.cpp), without the transition matrix
// or the covariance:
//   propagators (euler, midpoint, rk4), preintegration by propagation (the paper, section
//     3.1): propagated from the identity with zero gravity, the end state is the increment;
//   native preintegrators (manifold, tangent): their increment, which the bridge copies
//     unchanged into preint_reference (only the covariance and bias Jacobian change chart).
// tests/integrators/mean_only.cpp compares each plugin's increment_mean() with the full path
// bit for bit.
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

/// Preintegration by propagation's increment (the paper, section 3.1): the bridge's start
/// (identity, zero gravity) checked as a propagation's input, then `end_state(in, x_e)`
/// propagated from it; the end state is the increment (dR, dp, dv; bias entries left zero).
template <class EndState>
inline Status IncrementByPropagation(const PreintegrationInput& pin, EndState end_state,
                                     PreintIncrement& delta) {
  delta = PreintIncrement();
  const PropagationInput in = PreintegrationByPropagationStart(pin.window, pin.bg, pin.ba,
                                                               pin.noise);  // the bridge's start
  Status st = CheckPropagationInput(in);
  if (!st.ok()) return st;
  ImuState x_e;
  end_state(in, x_e);
  delta.dR = x_e.R;
  delta.dp = x_e.p;
  delta.dv = x_e.v;
  return st;
}

/// A native preintegrator's increment (dR, dp, dv; its bias entries left zero): `run` is the
/// scheme's recursion with its covariance switched off, writing a Preintegrated.
template <class RunWithoutCovariance>
inline Status IncrementWithoutCovariance(RunWithoutCovariance run, PreintIncrement& delta) {
  delta = PreintIncrement();
  Preintegrated out;
  const Status st = run(out);
  if (!st.ok()) return st;
  delta.dR = out.delta.dR;
  delta.dp = out.delta.dp;
  delta.dv = out.delta.dv;
  return st;
}

}  // namespace mean_only_detail

// Each function below gives the increment (dR, dp, dv; dbg = dba = 0) over in.window at the
// bias estimate (in.bg, in.ba), as the method's full preintegration gives it (see the file
// comment); in.noise is only checked (the mean does not depend on it). Each checks the input as
// the full run does and returns its error; never throws except std::bad_alloc while building a
// message. The plugins' increment_mean() calls them (plugin/kernel_plugin.h).

/// euler (Hold::Euler) and midpoint (Hold::Midpoint): PropagateHeld's end state.
template <Hold kHold>
inline Status HeldIncrementMean(const PreintegrationInput& pin, PreintIncrement& delta) {
  return mean_only_detail::IncrementByPropagation(pin, mean_only_detail::HeldEndState<kHold>,
                                                  delta);
}

/// euler and midpoint as a propagator plugin's kernel (plugin/kernel_plugin.h): PropagateHeld,
/// with HeldIncrementMean as its mean alone. Its noise simulation is the default (forward
/// cells); a hold whose samples stand for other cells says so on a struct derived from it.
template <Hold kHold>
struct HeldPropagation {
  Status operator()(const PropagationInput& in, PropagationResult& out) const {
    return PropagateHeld<kHold>(in, out);
  }
  static Status Mean(const PreintegrationInput& in, PreintIncrement& delta) {
    return HeldIncrementMean<kHold>(in, delta);
  }
};

/// rk4 with `steps` steps per knot interval: PropagateRk4's end state (its state-only mode).
inline Status Rk4IncrementMean(const PreintegrationInput& pin, int steps, PreintIncrement& delta) {
  return mean_only_detail::IncrementByPropagation(
      pin,
      [steps](const PropagationInput& in, ImuState& x_e) {
        PropagationResult r;
        IntegrateRk4Window(in, r, Outputs::State, steps, Isa::kAuto);
        x_e = r.x_e;
      },
      delta);
}

/// manifold and tangent: IntegrateManifold<false> / IntegrateTangent<false>'s increment, the
/// recursion with its covariance switched off.
inline Status ManifoldIncrementMean(const PreintegrationInput& in, PreintIncrement& delta) {
  return mean_only_detail::IncrementWithoutCovariance(
      [&in](Preintegrated& out) { return IntegrateManifold<false>(in, out); }, delta);
}
inline Status TangentIncrementMean(const PreintegrationInput& in, PreintIncrement& delta) {
  return mean_only_detail::IncrementWithoutCovariance(
      [&in](Preintegrated& out) { return IntegrateTangent<false>(in, out); }, delta);
}

}  // namespace imuconv::kernels
