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

std::vector<Preintegrated> ReferenceSchemes::compute(const std::vector<ImuSample>& samples, double t_s, double t_e,
                                                     const Vec3& bg, const Vec3& ba, const ImuNoise& noise) const {
  SampleWindow w;
  const Status st = MakeWindow(samples.data(), samples.size(), t_s, t_e, w);
  if (!st.ok()) throw Error(st.message());
  std::vector<Preintegrated> out;
  for (const auto& m : methods_) out.push_back(Preintegrate(reg_, m, w, bg, ba, noise));
  return out;
}

}  // namespace imuconv::check
