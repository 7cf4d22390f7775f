// The bridge between preintegration and propagation (paper, section 3), written once
// against the registry so that any propagator, any preintegrator and any pair of
// conventions compose with no pair-specific code.
#pragma once

#include <memory>
#include <string>
#include <string_view>

#include "imuconv/export.h"
#include "imuconv/prediction.h"
#include "imuconv/preintegrated.h"
#include "imuconv/registry.h"

namespace imuconv {

// Every measurement here is a Preintegrated (imuconv/preintegrated.h), whose `convention` and
// `jacobian_convention` say the charts of its cov and of J_bias's rows. Preintegrate and
// FromConvention return it in the reference charts (`preint_reference`: [theta, p, v, bg, ba],
// dR Exp(dtheta), additive p, v, Delta b; J_bias 9x6 with columns [bg, ba]); Express gives it
// in a named increment convention, in that convention's block order. The functions below that
// compute with a measurement take it in any charts and bring it into the reference ones first.

/// A preintegrate task's method, resolved once from its plugin id (no lookup by string per
/// interval). Exactly one of `propagator` and `preintegrator` is set; the conventions its path
/// needs are resolved with it.
struct PreintegrationMethod {
  std::string id;
  PluginKind kind = PluginKind::Propagator;  ///< Propagator or Preintegrator
  /// Wrapped by propagation (paper, section 3.1), with its native state convention and the
  /// state reference chart `left` it is run in.
  std::shared_ptr<const Propagator> propagator;
  std::shared_ptr<const StateConvention> native_state, reference_state;
  /// A native scheme, with its covariance and bias-Jacobian conventions and the increment
  /// reference chart `preint_reference` its output is brought into.
  std::shared_ptr<const Preintegrator> preintegrator;
  std::shared_ptr<const IncrementConvention> cov_convention, jacobian_convention,
      reference_increment;
};

/// Resolves `id` as a plugin of `kind` (Propagator or Preintegrator) with the conventions its
/// path needs. Throws Error listing the known ids for an unknown id or convention, and for
/// another kind.
IMUCONV_API PreintegrationMethod ResolvePreintegrationMethod(const Registry& reg, PluginKind kind,
                                                             std::string_view id);

/// Preintegrates with a resolved method: by propagation (paper, section 3.1: propagates from
/// the identity state with zero covariance and zero gravity, then converts with
/// (d dx_e|s / d dx_se)^{-1}) or natively, the result brought into the reference charts.
IMUCONV_API Preintegrated Preintegrate(const Registry& reg, const PreintegrationMethod& method,
                                       const SampleWindow& window, const Vec3& bg, const Vec3& ba,
                                       const ImuNoise& noise);

/// Preintegrate with the propagator `propagator`, resolved for this one call.
IMUCONV_API Preintegrated PreintegrateByPropagation(const Registry& reg,
                                                    std::string_view propagator,
                                                    const SampleWindow& window, const Vec3& bg,
                                                    const Vec3& ba, const ImuNoise& noise);

/// Preintegrate with the native preintegrator `preintegrator`, resolved for this one call.
IMUCONV_API Preintegrated PreintegrateNative(const Registry& reg, std::string_view preintegrator,
                                             const SampleWindow& window, const Vec3& bg,
                                             const Vec3& ba, const ImuNoise& noise);

/// Expresses a measurement in a named increment convention: cov in `convention`, J_bias's rows
/// in that convention's bias-Jacobian chart (IncrementConvention::jacobian_convention()), both
/// in their block orders; the labels say so.
IMUCONV_API Preintegrated Express(const Registry& reg, const Preintegrated& m,
                                  std::string_view convention);
/// Brings a measurement into the reference charts, from the charts its labels name (e.g. to
/// import numbers dumped from GTSAM). An empty `jacobian_convention` means the one that
/// `convention` names for its bias Jacobian. Throws Error for an unknown id.
IMUCONV_API Preintegrated FromConvention(const Registry& reg, const Preintegrated& m);

/// Paper, section 3.2 (eq. prop-cov): propagation by preintegration. Phi_e|s and
/// Sigma_e|s = Phi Sigma_s Phi^T + G Sigma_dx G^T, with x_s, cov_s and the results in the
/// named state convention.
IMUCONV_API PropagationResult PropagateByPreintegration(const Registry& reg, const Preintegrated& m,
                                                        const ImuState& x_s, const Mat15& cov_s,
                                                        std::string_view state_convention,
                                                        const Vec3& gravity);

/// First-order bias correction in the chart of `jacobian_convention` (GTSAM's
/// biasCorrectedDelta when that chart is GTSAM's): retract(delta, J_chart (b - b_hat)).
IMUCONV_API PreintIncrement BiasCorrectedDelta(const Registry& reg, const Preintegrated& m,
                                               std::string_view jacobian_convention, const Vec3& bg,
                                               const Vec3& ba);

enum class ResidualKind {
  Gtsam,    ///< PreintegrationBase::computeError: Log(R_e^T R_pred), R_e^T(p_pred - p_e),
            ///< R_e^T(v_pred - v_e); bias b_e - b_pred
  Forster,  ///< Forster et al.: Log(R_pred^T R_e), R_s^T(p_e - p_pred), R_s^T(v_e - v_pred); bias
            ///< b_e - b_pred
};

/// A 15-dim residual [theta, p, v, bg, ba] with its Jacobians with respect to the start
/// state (including the start bias, through the bias Jacobian) and the end state, both in
/// `state_convention`, and its covariance by the chain rule (paper, eq. residual-cov).
struct Residual {
  Vec15 r = Vec15::Zero();
  Mat15 H_start = Mat15::Zero();
  Mat15 H_end = Mat15::Zero();
  Mat15 cov = Mat15::Zero();
  /// d r / d dx_se: the derivative with respect to a perturbation of the measured increment
  /// (before bias correction) in preint_reference; multiply by
  /// Registry::conversion(conv, "preint_reference", m.delta) for another increment convention.
  Mat15 H_increment = Mat15::Zero();
};

/// The start bias is x_s's; the increment is first-order bias-corrected from m.bg_hat/ba_hat
/// to it in preint_reference (exact first order in any chart).
IMUCONV_API Residual ComputeResidual(const Registry& reg, ResidualKind kind, const Preintegrated& m,
                                     const ImuState& x_s, const ImuState& x_e,
                                     std::string_view state_convention, const Vec3& gravity);

}  // namespace imuconv
