// The prediction equations that bridge preintegration and propagation (paper,
// eq. prop-by-int-rot..prop-by-int-b), and their Jacobians in the reference charts.
#pragma once

#include "imuconv/reference_charts.h"
#include "imuconv/so3.h"
#include "imuconv/types.h"

namespace imuconv {

/// x_{e|s} = f(x_s, Delta x_se): R_e = R_s dR, p_e = p_s + v_s dt + g dt^2/2 + R_s dp,
/// v_e = v_s + R_s dv + g dt, b_e = b_s + Delta b.
inline ImuState Predict(const ImuState& xs, const PreintIncrement& d, double dt, const Vec3& g) {
  ImuState xe;
  xe.R = xs.R * d.dR;
  xe.p = xs.p + xs.v * dt + 0.5 * dt * dt * g + xs.R * d.dp;
  xe.v = xs.v + xs.R * d.dv + g * dt;
  xe.bg = xs.bg + d.dbg;
  xe.ba = xs.ba + d.dba;
  return xe;
}

/// Jacobians of Predict with the increment held fixed, in the reference charts:
///   F_s = d local_left(x_e, f(retract_left(x_s, e), D)) / d e,
///   G   = d local_left(x_e, f(x_s, retract_pref(D, w))) / d w   (paper's G_{e|s}).
/// Either pointer may be null.
inline void PredictJacobians(const ImuState& xs, const PreintIncrement& d, double dt, Mat15* F_s,
                             Mat15* G) {
  using namespace left_idx;
  if (F_s) {
    // R_s -> Exp(e) R_s moves R_s dp and R_s dv by e x (.), so -[.]x e.
    F_s->setIdentity();
    F_s->block<3, 3>(p, v) = dt * Mat3::Identity();
    F_s->block<3, 3>(p, theta) = -so3::skew(xs.R * d.dp);
    F_s->block<3, 3>(v, theta) = -so3::skew(xs.R * d.dv);
  }
  if (G) {
    // R_s dR Exp(w) = Exp(R_e w) R_e, so the left rotation error is R_e w.
    G->setZero();
    G->block<3, 3>(theta, pref_idx::theta) = xs.R * d.dR;
    G->block<3, 3>(p, pref_idx::p) = xs.R;
    G->block<3, 3>(v, pref_idx::v) = xs.R;
    G->block<3, 3>(bg, pref_idx::bg).setIdentity();
    G->block<3, 3>(ba, pref_idx::ba).setIdentity();
  }
}

}  // namespace imuconv
