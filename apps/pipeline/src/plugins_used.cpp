#include "plugins_used.h"

#include <set>
#include <utility>

namespace imuconv::pipeline {

std::vector<const PluginInfo*> PluginsUsed(const PipelineSpec& s, const Registry& reg,
                                           const std::map<std::string, std::vector<MeasRecord>>& files) {
  std::set<std::pair<PluginKind, std::string>> used;
  const auto add = [&](PluginKind kind, const std::string& id) {
    if (!id.empty() && reg.has(kind, id)) used.emplace(kind, id);
  };
  const auto state = [&](const std::string& id) { add(PluginKind::StateConvention, id); };
  const auto preint = [&](const std::string& id) {
    add(PluginKind::PreintConvention, id);
    // Expressing a measurement in a convention uses its bias-Jacobian chart too.
    if (reg.has(PluginKind::PreintConvention, id)) add(PluginKind::PreintConvention, reg.info(PluginKind::PreintConvention, id).jacobian_convention);
  };
  const auto cov = [&](const CovSpec& c, const auto& conv) {
    if (c.given && c.m().convention) conv(*c.m().convention);
  };
  bool measurements = false;  // some task holds preintegrated measurements (preint_reference)
  for (const auto& t : s.tasks) {
    if (const auto* x = std::get_if<PropagateTask>(&t.body)) {
      add(PluginKind::Propagator, x->propagator);
      if (reg.has(PluginKind::Propagator, x->propagator)) state(reg.info(PluginKind::Propagator, x->propagator).native_convention);
      state(x->convention);
      cov(x->cov, state);
    } else if (const auto* x = std::get_if<PreintegrateTask>(&t.body)) {
      const PluginKind kind = x->native ? PluginKind::Preintegrator : PluginKind::Propagator;
      add(kind, x->method_id);
      if (reg.has(kind, x->method_id)) {
        const PluginInfo& info = reg.info(kind, x->method_id);
        // A propagator's native chart is a state convention; a preintegrator's are increment ones.
        if (x->native) {
          preint(info.native_convention);
          preint(info.jacobian_convention);
        } else {
          state(info.native_convention);
        }
      }
      for (const auto& c : x->conventions) preint(c);
      measurements = true;
    } else if (const auto* x = std::get_if<PropByPreintTask>(&t.body)) {
      state(x->convention);
      cov(x->cov, state);
      measurements = true;
    } else if (const auto* x = std::get_if<ConvertTask>(&t.body)) {
      using W = ConvertTask::What;
      const bool state_kind = x->what == W::StateJacobian || x->what == W::StateCovariance || x->what == W::StateTransition;
      const auto conv = [&](const std::string& id) { state_kind ? state(id) : preint(id); };
      if (x->from) conv(*x->from);
      conv(x->to);
      if (x->matrix && x->matrix->convention) conv(*x->matrix->convention);
      if (!state_kind) measurements = true;
    } else if (const auto* x = std::get_if<ResidualTask>(&t.body)) {
      state(x->convention);
      measurements = true;
    } else if (const auto* x = std::get_if<BiasUpdateTask>(&t.body)) {
      for (const auto& c : x->charts) preint(c);
      measurements = true;
    }
  }
  for (const auto& [path, records] : files)
    for (const auto& r : records) {
      preint(r.convention);
      preint(r.jacobian_convention);
    }
  // Every conversion is composed through its kind's reference chart (registry.h).
  bool any_state = false, any_preint = measurements;
  for (const auto& [kind, id] : used) {
    any_state = any_state || kind == PluginKind::StateConvention;
    any_preint = any_preint || kind == PluginKind::PreintConvention;
  }
  if (any_state) state("left");
  if (any_preint) add(PluginKind::PreintConvention, "preint_reference");
  std::vector<const PluginInfo*> out;
  out.reserve(used.size());
  for (const auto& [kind, id] : used) out.push_back(&reg.info(kind, id));
  return out;
}

}  // namespace imuconv::pipeline
