// Conversion Jacobians between two resolved conventions, with no lookup by id.
//
// Every convention is related to its kind's reference chart (`left` for states,
// `preint_reference` for increments), and
//   conversion(A, B, x) = J_{B <- ref}(x) * J_{ref <- A}(x),
// the exact chain rule of d local_B(x, retract_A(x, d)) / d d at d = 0. Each factor is the
// convention's analytic Jacobian or, where it gives none, Ridders' differences of its own
// retract/local against the reference chart. Registry's id-based accessors call these.
#pragma once

#include "imuconv/error_state.h"
#include "imuconv/export.h"
#include "imuconv/propagator.h"
#include "imuconv/types.h"

namespace imuconv {

/// J_{ref <- c}(x) = d local_ref(x, retract_c(x, d)) / d d at d = 0.
IMUCONV_API Mat15 ToReference(const ErrorState& c, const ImuState& x);
IMUCONV_API Mat15 ToReference(const PreintConvention& c, const PreintIncrement& x);
/// J_{c <- ref}(x) = d local_c(x, retract_ref(x, e)) / d e at e = 0.
IMUCONV_API Mat15 FromReference(const ErrorState& c, const ImuState& x);
IMUCONV_API Mat15 FromReference(const PreintConvention& c, const PreintIncrement& x);
/// J_{to <- from}(x); the identity when both are one convention (same id).
IMUCONV_API Mat15 Conversion(const ErrorState& from, const ErrorState& to, const ImuState& x);
IMUCONV_API Mat15 Conversion(const PreintConvention& from, const PreintConvention& to, const PreintIncrement& x);
/// J S J^T (symmetrized) with J = Conversion(from, to, x).
IMUCONV_API Mat15 ConvertCovariance(const ErrorState& from, const ErrorState& to, const ImuState& x, const Mat15& S);
/// J_e Phi J_s^{-1}, with J_s^{-1} = Conversion(to, from, x_s).
IMUCONV_API Mat15 ConvertTransition(const ErrorState& from, const ErrorState& to, const ImuState& x_s,
                                    const ImuState& x_e, const Mat15& Phi);

/// Runs `prop` (whose native state convention is `native`) with in.cov_s in `convention`, and
/// returns Phi and cov in `convention`. Throws Error naming the propagator when it fails.
IMUCONV_API PropagationResult PropagateIn(const Propagator& prop, const ErrorState& native,
                                          const ErrorState& convention, const PropagationInput& in);

}  // namespace imuconv
