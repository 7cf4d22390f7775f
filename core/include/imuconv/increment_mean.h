// The optional mean-only integration of a propagator or preintegrator plugin
// (Propagator::increment_mean, Preintegrator::increment_mean): the increment (dR, dp, dv) a
// method's full preintegration gives through the bridge (registry/src/bridge.cpp), without the
// transition matrix, the covariance or the bias Jacobian. A host that re-integrates one window
// many times and needs only the end value (imuconv montecarlo's trials, docs/montecarlo.md)
// calls it; a plugin that does not provide it is served by its full integration, as before.
//
// What it must equal: for a propagator, the end state propagated from the identity with zero
// gravity at the bias estimate (preintegration by propagation, the note's section 3.1,
// eq. prop-by-int-rot..b with R_s = I, p_s = v_s = 0, g = 0; PreintegrationByPropagationStart);
// for a native preintegrator, its own increment, which the bridge copies unchanged into
// preint_reference. A host must not take that on trust: montecarlo compares the mean-only
// nominal increment with the full path's before it uses it (kMeanOffsetSigmas).
#pragma once

#include "imuconv/status.h"

namespace imuconv {

/// The message of increment_mean()'s default. Short enough for std::string's small buffer, so
/// that the default (noexcept) allocates nothing and cannot throw.
inline constexpr char kIncrementMeanNotProvided[] = "not provided";

/// What a plugin without a mean-only integration returns from increment_mean().
inline Status IncrementMeanNotProvided() noexcept {
  return Status::Error(kIncrementMeanNotProvided);
}

/// True when `st` is increment_mean()'s "not provided" (rather than bad input or a failure).
inline bool IsIncrementMeanNotProvided(const Status& st) noexcept {
  return !st.ok() && st.message() == kIncrementMeanNotProvided;
}

}  // namespace imuconv
