// A preintegrated measurement (the note, eq. Preint: [b_s, z_{s:e}, q] -> [Delta x_se, J_bs,
// Sigma_Delta x]), the one type every part holds: a native preintegrator writes it, the
// bridge brings it into the reference charts and expresses it in any increment convention,
// the pipeline reads and writes it, the Python module and refcase hand it on. The charts its
// matrices are in are members, so a measurement always says what its numbers mean.
#pragma once

#include <cmath>
#include <string>

#include "imuconv/reference_charts.h"
#include "imuconv/types.h"

namespace imuconv {

struct Preintegrated {
  // The plugin ABI (preintegrator.h, since kPluginAbiVersion 2): a native preintegrator writes the
  // members from dt to J_bias, which keep the order and layout they had as the plugin's output
  // type; it never writes the two labels below them. The host sets those from the plugin's
  // cov_convention() and jacobian_convention() (registry/src/bridge.cpp), so no std::string
  // is made or freed on the plugin's side of the boundary.
  double dt = 0.0;
  PreintIncrement delta;
  Vec3 bg_hat = Vec3::Zero(), ba_hat = Vec3::Zero();  ///< bias estimate it was integrated with
  /// 15x15 covariance of the increment (bias random walk included), in `convention`'s chart and
  /// block order.
  Mat15 cov = Mat15::Zero();
  /// Rows: the (theta, p, v) blocks of `jacobian_convention`'s chart, in its block order.
  /// Columns: an additive change of the bias estimate, in that convention's bias order.
  Mat96 J_bias = Mat96::Zero();

  /// Id of the increment convention `cov` is in; empty while not stated (a kernel's or a
  /// plugin's raw output, a file's undeclared chart). The bridge returns every measurement
  /// with its charts stated, and refuses to compute with one whose charts are not.
  std::string convention;
  /// Id of the increment convention of J_bias's rows; empty: the one `convention` names for
  /// its bias Jacobian (IncrementConvention::jacobian_convention()).
  std::string jacobian_convention;

  /// Whether cov and J_bias are both in the reference chart `preint_reference` ([theta, p, v,
  /// bg, ba], dR Exp(dtheta), additive p, v and Delta b; J_bias columns [bg, ba]): what
  /// Preintegrate and FromConvention return.
  bool in_reference_charts() const {
    return convention == ReferenceChart<PreintIncrement>::id &&
           jacobian_convention == ReferenceChart<PreintIncrement>::id;
  }
};

/// Whether every number a preintegrator writes (dt, the increment, cov and J_bias) is finite.
inline bool AllFinite(const Preintegrated& m) {
  return std::isfinite(m.dt) && m.delta.dR.allFinite() && m.delta.dp.allFinite() &&
         m.delta.dv.allFinite() && m.delta.dbg.allFinite() && m.delta.dba.allFinite() &&
         m.cov.allFinite() && m.J_bias.allFinite();
}

}  // namespace imuconv
