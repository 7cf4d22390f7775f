// The two reference charts every convention is related through.
//
// State reference, the paper's left error state (eq. left-dpr..left-dba), order
// [p, theta, v, bg, ba]:  p = p^ + dp, R = Exp(dtheta) R^, v = v^ + dv, b = b^ + db.
//
// Increment reference `preint_reference`, order [theta, p, v, bg, ba]:
//   dR = dR^ Exp(dtheta), dp = dp^ + dp, dv = dv^ + dv, Delta b = Delta b^ + db.
// (The paper's j perturbation with the bias entry taken with a plus sign.)
#pragma once

#include "imuconv/block_order.h"
#include "imuconv/so3.h"
#include "imuconv/types.h"

namespace imuconv {

/// Block offsets of the state reference chart (derived from kLeftOrder).
namespace left_idx {
constexpr int p = kLeftOrder.offset(Block::p), theta = kLeftOrder.offset(Block::theta),
              v = kLeftOrder.offset(Block::v), bg = kLeftOrder.offset(Block::bg),
              ba = kLeftOrder.offset(Block::ba);
}
/// Block offsets of the increment reference chart (derived from kPreintReferenceOrder).
namespace pref_idx {
constexpr int theta = kPreintReferenceOrder.offset(Block::theta),
              p = kPreintReferenceOrder.offset(Block::p),
              v = kPreintReferenceOrder.offset(Block::v),
              bg = kPreintReferenceOrder.offset(Block::bg),
              ba = kPreintReferenceOrder.offset(Block::ba);
}

inline void LeftRetract(const ImuState& x, const Vec15& d, ImuState& y) {
  y.p = x.p + d.segment<3>(left_idx::p);
  y.R = so3::Exp(d.segment<3>(left_idx::theta)) * x.R;
  y.v = x.v + d.segment<3>(left_idx::v);
  y.bg = x.bg + d.segment<3>(left_idx::bg);
  y.ba = x.ba + d.segment<3>(left_idx::ba);
}

inline void LeftLocal(const ImuState& x, const ImuState& y, Vec15& d) {
  d.segment<3>(left_idx::p) = y.p - x.p;
  d.segment<3>(left_idx::theta) = so3::Log(y.R * x.R.transpose());
  d.segment<3>(left_idx::v) = y.v - x.v;
  d.segment<3>(left_idx::bg) = y.bg - x.bg;
  d.segment<3>(left_idx::ba) = y.ba - x.ba;
}

inline void PreintReferenceRetract(const PreintIncrement& x, const Vec15& d, PreintIncrement& y) {
  y.dR = x.dR * so3::Exp(d.segment<3>(pref_idx::theta));
  y.dp = x.dp + d.segment<3>(pref_idx::p);
  y.dv = x.dv + d.segment<3>(pref_idx::v);
  y.dbg = x.dbg + d.segment<3>(pref_idx::bg);
  y.dba = x.dba + d.segment<3>(pref_idx::ba);
}

inline void PreintReferenceLocal(const PreintIncrement& x, const PreintIncrement& y, Vec15& d) {
  d.segment<3>(pref_idx::theta) = so3::Log(x.dR.transpose() * y.dR);
  d.segment<3>(pref_idx::p) = y.dp - x.dp;
  d.segment<3>(pref_idx::v) = y.dv - x.dv;
  d.segment<3>(pref_idx::bg) = y.dbg - x.dbg;
  d.segment<3>(pref_idx::ba) = y.dba - x.dba;
}

/// The reference chart of each kind, for code written once over the value type.
template <class Value>
struct ReferenceChart;

template <>
struct ReferenceChart<ImuState> {
  static constexpr const char* id = "left";
  static constexpr BlockOrder order = kLeftOrder;
  static void retract(const ImuState& x, const Vec15& d, ImuState& y) { LeftRetract(x, d, y); }
  static void local(const ImuState& x, const ImuState& y, Vec15& d) { LeftLocal(x, y, d); }
};

template <>
struct ReferenceChart<PreintIncrement> {
  static constexpr const char* id = "preint_reference";
  static constexpr BlockOrder order = kPreintReferenceOrder;
  static void retract(const PreintIncrement& x, const Vec15& d, PreintIncrement& y) {
    PreintReferenceRetract(x, d, y);
  }
  static void local(const PreintIncrement& x, const PreintIncrement& y, Vec15& d) {
    PreintReferenceLocal(x, y, d);
  }
};

}  // namespace imuconv
