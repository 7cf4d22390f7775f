// A result that comes out with an inf or NaN is an error, never returned: the arrays would be
// a wrong answer given in silence. The pipeline refuses the same in its writer
// (io/json_writer.cpp: "produced a non-finite number"); inputs that pass every check can
// still overflow (an accelerometer value of 1e308, a covariance of 1e308 propagated).
#pragma once

#include <string>

#include "arrays.h"
#include "imuconv/bridge.h"
#include "imuconv/propagator.h"

namespace imuconv::python {

namespace finite_detail {

inline void Require(bool finite, const char* call, const char* field) {
  if (!finite)
    throw py::value_error(
        std::string(call) + ": produced a non-finite number (" + field +
        "); the inputs are too large for double precision (samples, noise, covariance or state)");
}

inline void RequireIncrement(const PreintIncrement& d, const char* call) {
  Require(d.dR.allFinite(), call, "delta.dR");
  Require(d.dp.allFinite(), call, "delta.dp");
  Require(d.dv.allFinite(), call, "delta.dv");
  Require(d.dbg.allFinite() && d.dba.allFinite(), call, "delta bias walk");
}

}  // namespace finite_detail

/// `call` names the function in the message ("preintegrate: produced a non-finite number (cov)").
inline Preintegrated FiniteMeasurement(Preintegrated m, const char* call) {
  finite_detail::Require(std::isfinite(m.dt), call, "dt");
  finite_detail::RequireIncrement(m.delta, call);
  finite_detail::Require(m.J_bias.allFinite(), call, "J_bias");
  finite_detail::Require(m.cov.allFinite(), call, "cov");
  return m;
}

/// A conversion's matrix (a Jacobian, a covariance or a transition in another convention):
/// "convert_covariance: produced a non-finite number (result)".
inline Mat15 FiniteConversion(const Mat15& m, const char* call) {
  finite_detail::Require(m.allFinite(), call, "result");
  return m;
}

inline PropagationResult FinitePropagation(PropagationResult p, const char* call) {
  finite_detail::Require(p.x_e.R.allFinite() && p.x_e.p.allFinite() && p.x_e.v.allFinite() &&
                             p.x_e.bg.allFinite() && p.x_e.ba.allFinite(),
                         call, "x_e");
  finite_detail::Require(p.Phi.allFinite(), call, "Phi");
  finite_detail::Require(p.cov.allFinite(), call, "cov");
  return p;
}

inline Residual FiniteResidual(Residual r, const char* call) {
  finite_detail::Require(r.r.allFinite(), call, "r");
  finite_detail::Require(r.H_start.allFinite() && r.H_end.allFinite() && r.H_increment.allFinite(),
                         call, "Jacobians");
  finite_detail::Require(r.cov.allFinite(), call, "cov");
  return r;
}

}  // namespace imuconv::python
