// The kernel of the rk4 propagator: fourth-order integration in the `left` error state of the
// state, the transition matrix and the covariance, with the gyro and accel input interpolated
// linearly between knots; each knot interval may be split into `substeps` equal steps of length
// h (the plugin uses 1; tests halve the step with 2). Rotation by the fourth-order Magnus
// expansion, everything else by quadratures at the nodes 0, h/2, h, the covariance by variation
// of constants (the note, eq. prop-cov); the derivation is with the code,
// core/src/kernels/rk4_window.h.
//
// The code is compiled in imuconv_core only, once per instruction set, behind the same
// instances and dispatch as the preintegration kernel (kernels/preintegration.h, Isa): the
// plugin, imuconv montecarlo's mean-only trials, the benchmarks and the tests all call this one
// compiled copy, and every instance and output mode computes the state with the same IEEE
// operations (rk4_window.h, "Instances"), so the state does not depend on what else is asked.
#pragma once

#include "imuconv/export.h"
#include "imuconv/kernels/common.h"          // Outputs
#include "imuconv/kernels/preintegration.h"  // Isa, IsaAvailable
#include "imuconv/propagator.h"
#include "imuconv/status.h"

namespace imuconv::kernels {

/// Integrates the window of `in` from in.x_s with `substeps` (>= 1) steps per knot interval,
/// without checking the input (see PropagateRk4): fills out.x_e, and out.Phi and out.cov as
/// `outputs` asks. `isa` chooses the instance (tests and benchmarks; it must be available,
/// IsaAvailable); kAuto runs the widest this CPU has, kPortable and kBaseline the
/// default-target code. Allocates nothing.
IMUCONV_API void IntegrateRk4Window(const PropagationInput& in, PropagationResult& out,
                                    Outputs outputs, int substeps, Isa isa);

/// The propagator entry point: checks the input (substeps >= 1, `isa` available, the window
/// and state, CheckPropagationInput), then integrates with every output.
IMUCONV_API Status PropagateRk4(const PropagationInput& in, PropagationResult& out,
                                int substeps = 1, Isa isa = Isa::kAuto);

/// IntegrateRk4Window with the output mode as a template argument.
template <Outputs kOut = Outputs::All>
inline void IntegrateRk4(const PropagationInput& in, PropagationResult& out, int substeps = 1,
                         Isa isa = Isa::kAuto) {
  IntegrateRk4Window(in, out, kOut, substeps, isa);
}

}  // namespace imuconv::kernels
