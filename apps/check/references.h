// The reference numbers a user's measurement is compared with: preintegration by propagation
// (the note, section 3.1; registry/include/imuconv/bridge.h) over the measurement's interval,
// from its bias estimate, with each scheme check knows:
//   euler     zero-order hold: each sample held over the step that starts at it (GTSAM's
//             discretization; GTSAM's ManifoldPreintegration numbers agree with it to about
//             1e-13 in the scale-aware d),
//   midpoint  the mean of consecutive samples held over each step (GTSAM's numbers on its
//             `mid` input agree with it to about 1e-12),
//   rk4       linear interpolation between samples, to 4th order,
// and every registered native preintegrator (tangent, manifold, vins_fusion, basalt, ...):
// each is a scheme of its own, not a round-off of one of the three. GTSAM's
// TangentPreintegration integrates the same zero-order hold by a first-order recursion in the
// tangent space (its increment differs from euler's by up to d = 0.2 over 10 s of fast
// rotation); VINS-Fusion's and Basalt's bias Jacobians are first-order approximations (over
// 1 s intervals of the case smooth-2, up to d = 0.08 and 0.7 from the nearest of the three
// propagators). Numbers from those systems are explained by their own scheme, by name.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "imuconv/bridge.h"

namespace imuconv::check {

/// The three propagators every check compares with (preintegration by propagation).
inline constexpr std::array<const char*, 3> kPropagatorSchemes = {"euler", "midpoint", "rk4"};

/// The schemes, resolved once (ResolvePreintegrationMethod).
class ReferenceSchemes {
 public:
  explicit ReferenceSchemes(const Registry& reg);
  /// The schemes' ids: kPropagatorSchemes, then the registered preintegrators in the
  /// registry's order.
  const std::vector<std::string>& ids() const { return ids_; }
  /// One reference per scheme, in ids() order, in the reference charts (Preintegrated), or,
  /// for a scheme that cannot run on this interval (Basalt's knots less than 1 ns apart, say),
  /// nothing and in `not_applicable` the reason: one scheme that cannot run must not sink the
  /// judgment by the others. Throws imuconv::Error when [t_s, t_e] is not covered by the
  /// samples (then no scheme can run).
  struct Reference {
    std::optional<Preintegrated> m;
    std::string not_applicable;  ///< why m is empty
  };
  std::vector<Reference> compute(const std::vector<ImuSample>& samples, double t_s, double t_e,
                                 const Vec3& bg, const Vec3& ba, const ImuNoise& noise) const;

 private:
  const Registry& reg_;
  std::vector<std::string> ids_;
  std::vector<PreintegrationMethod> methods_;
};

}  // namespace imuconv::check
