// The two reference charts every convention is related through.
//
// State reference, the paper's left error state (eq. left-dpr..left-dba), order
// [p, theta, v, bg, ba]:  p = p^ + dp, R = Exp(dtheta) R^, v = v^ + dv, b = b^ + db.
//
// Increment reference `preint_reference`, order [theta, p, v, bg, ba]:
//   dR = dR^ Exp(dtheta), dp = dp^ + dp, dv = dv^ + dv, Delta b = Delta b^ + db.
// (The paper's j perturbation with the bias entry taken with a plus sign.)
#pragma once

#include "imuconv/so3.h"
#include "imuconv/types.h"

namespace imuconv {

/// Block offsets of the state reference chart.
namespace left_idx {
constexpr int p = 0, theta = 3, v = 6, bg = 9, ba = 12;
}
/// Block offsets of the increment reference chart.
namespace pref_idx {
constexpr int theta = 0, p = 3, v = 6, bg = 9, ba = 12;
}

inline void LeftRetract(const ImuState& x, const Vec15& d, ImuState& y) {
  y.p = x.p + d.segment<3>(0);
  y.R = so3::Exp(d.segment<3>(3)) * x.R;
  y.v = x.v + d.segment<3>(6);
  y.bg = x.bg + d.segment<3>(9);
  y.ba = x.ba + d.segment<3>(12);
}

inline void LeftLocal(const ImuState& x, const ImuState& y, Vec15& d) {
  d.segment<3>(0) = y.p - x.p;
  d.segment<3>(3) = so3::Log(y.R * x.R.transpose());
  d.segment<3>(6) = y.v - x.v;
  d.segment<3>(9) = y.bg - x.bg;
  d.segment<3>(12) = y.ba - x.ba;
}

inline void PreintReferenceRetract(const PreintIncrement& x, const Vec15& d, PreintIncrement& y) {
  y.dR = x.dR * so3::Exp(d.segment<3>(0));
  y.dp = x.dp + d.segment<3>(3);
  y.dv = x.dv + d.segment<3>(6);
  y.dbg = x.dbg + d.segment<3>(9);
  y.dba = x.dba + d.segment<3>(12);
}

inline void PreintReferenceLocal(const PreintIncrement& x, const PreintIncrement& y, Vec15& d) {
  d.segment<3>(0) = so3::Log(x.dR.transpose() * y.dR);
  d.segment<3>(3) = y.dp - x.dp;
  d.segment<3>(6) = y.dv - x.dv;
  d.segment<3>(9) = y.dbg - x.dbg;
  d.segment<3>(12) = y.dba - x.dba;
}

}  // namespace imuconv
