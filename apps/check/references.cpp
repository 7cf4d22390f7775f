#include "references.h"

namespace imuconv::check {

ReferenceSchemes::ReferenceSchemes(const Registry& reg) : reg_(reg) {
  for (const char* id : kPropagatorSchemes) {
    ids_.push_back(id);
    methods_.push_back(ResolvePreintegrationMethod(reg, PluginKind::Propagator, id));
  }
  for (const auto& id : reg.ids(PluginKind::Preintegrator)) {
    ids_.push_back(id);
    methods_.push_back(ResolvePreintegrationMethod(reg, PluginKind::Preintegrator, id));
  }
}

std::vector<ReferenceSchemes::Reference> ReferenceSchemes::compute(
    const std::vector<ImuSample>& samples, double t_s, double t_e, const Vec3& bg, const Vec3& ba,
    const ImuNoise& noise) const {
  SampleWindow w;
  const Status st = MakeWindow(samples.data(), samples.size(), t_s, t_e, w);
  if (!st.ok()) throw Error(st.message());
  std::vector<Reference> out(methods_.size());
  for (std::size_t s = 0; s < methods_.size(); ++s) {
    try {
      out[s].m = Preintegrate(reg_, methods_[s], w, bg, ba, noise);
      // A scheme whose numbers overflow at this bias estimate (a gyro bias of 1e160 rad/s, say)
      // is no reference: against inf and NaN every explanation ties, and a verdict would be
      // noise. With no scheme left the measurement is refused as bad input (check.cpp).
      if (!AllFinite(*out[s].m)) {
        out[s].m.reset();
        out[s].not_applicable =
            "its increment, bias Jacobian or covariance is not finite at the measurement's bias "
            "estimate (are bias_estimate's bg in rad/s and ba in m/s^2?)";
      }
    } catch (const Error& e) {  // the scheme's own refusal (a Status from its plugin)
      out[s].not_applicable = e.what();
    }
  }
  return out;
}

}  // namespace imuconv::check
