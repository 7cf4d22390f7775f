// Conversion Jacobians between two resolved conventions, with no lookup by id.
//
// Every convention is related to its kind's reference chart (`left` for states,
// `preint_reference` for increments), and
//   conversion(A, B, x) = J_{B <- ref}(x) * J_{ref <- A}(x),
// the exact chain rule of d local_B(x, retract_A(x, d)) / d d at d = 0. Each factor is the
// convention's analytic Jacobian or, where it gives none, Ridders' differences of its own
// retract/local against the reference chart. Registry's id-based accessors call these.
#pragma once

#include "imuconv/chart.h"
#include "imuconv/export.h"
#include "imuconv/propagator.h"
#include "imuconv/types.h"

namespace imuconv {

/// J_ref_this(x) = d local_ref(x, retract_c(x, d)) / d d at d = 0: the chart's analytic
/// Jacobian, or Ridders' differences when it gives none.
template <class Value>
IMUCONV_API Mat15 ToReference(const Chart<Value>& c, const Value& x);
/// J_this_ref(x) = d local_c(x, retract_ref(x, e)) / d e at e = 0.
template <class Value>
IMUCONV_API Mat15 FromReference(const Chart<Value>& c, const Value& x);
/// J_to_from(x) = J_to_ref(x) J_ref_from(x); the identity when both are one convention (same id).
template <class Value>
IMUCONV_API Mat15 Conversion(const Chart<Value>& from, const Chart<Value>& to, const Value& x);
/// J S J^T (symmetrized) with J = Conversion(from, to, x).
template <class Value>
IMUCONV_API Mat15 ConvertCovariance(const Chart<Value>& from, const Chart<Value>& to,
                                    const Value& x, const Mat15& S);

/// J_e Phi J_s^{-1}, with J_e = Conversion(from, to, x_e) and J_s^{-1} = Conversion(to, from, x_s).
template <class Value>
IMUCONV_API Mat15 ConvertTransition(const Chart<Value>& from, const Chart<Value>& to,
                                    const Value& x_s, const Value& x_e, const Mat15& Phi);

/// Runs `prop` (whose native state convention is `native`) with in.cov_s in `convention`, and
/// returns Phi and cov in `convention`. Throws Error naming the propagator when it fails.
IMUCONV_API PropagationResult PropagateIn(const Propagator& prop, const StateConvention& native,
                                          const StateConvention& convention,
                                          const PropagationInput& in);

// Compiled for the two kinds in the registry library.
#define IMUCONV_CONVERSION_INSTANCES(EXTERN, V)                                                \
  EXTERN template IMUCONV_API Mat15 ToReference<V>(const Chart<V>&, const V&);                 \
  EXTERN template IMUCONV_API Mat15 FromReference<V>(const Chart<V>&, const V&);               \
  EXTERN template IMUCONV_API Mat15 Conversion<V>(const Chart<V>&, const Chart<V>&, const V&); \
  EXTERN template IMUCONV_API Mat15 ConvertCovariance<V>(const Chart<V>&, const Chart<V>&,     \
                                                         const V&, const Mat15&);              \
  EXTERN template IMUCONV_API Mat15 ConvertTransition<V>(const Chart<V>&, const Chart<V>&,     \
                                                         const V&, const V&, const Mat15&);
IMUCONV_CONVERSION_INSTANCES(extern, ImuState)
IMUCONV_CONVERSION_INSTANCES(extern, PreintIncrement)

}  // namespace imuconv
