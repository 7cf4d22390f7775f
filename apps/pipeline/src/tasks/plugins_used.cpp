#include "plugins_used.h"

#include "../spec/pipeline_spec.h"
#include "task.h"

namespace imuconv::pipeline {

void PluginUse::add(PluginKind kind, const std::string& id) {
  if (!id.empty() && reg_.has(kind, id)) used_.emplace(kind, id);
}

void PluginUse::increment(const std::string& id) {
  add(PluginKind::IncrementConvention, id);
  if (reg_.has(PluginKind::IncrementConvention, id))
    add(PluginKind::IncrementConvention,
        reg_.info(PluginKind::IncrementConvention, id).jacobian_convention);
}

void PluginUse::propagator(const std::string& id) {
  add(PluginKind::Propagator, id);
  if (reg_.has(PluginKind::Propagator, id))
    state(reg_.info(PluginKind::Propagator, id).native_convention);
}

void PluginUse::state_cov(const CovSpec& cov) {
  if (cov.given && cov.m().convention) state(*cov.m().convention);
}

std::vector<const PluginInfo*> PluginUse::list() {
  // Every conversion is composed through its kind's reference chart (registry.h).
  bool any_state = false, any_preint = measurements_;
  for (const auto& [kind, id] : used_) {
    any_state = any_state || kind == PluginKind::StateConvention;
    any_preint = any_preint || kind == PluginKind::IncrementConvention;
  }
  if (any_state) state("left");
  if (any_preint) add(PluginKind::IncrementConvention, "preint_reference");
  std::vector<const PluginInfo*> out;
  out.reserve(used_.size());
  for (const auto& [kind, id] : used_) out.push_back(&reg_.info(kind, id));
  return out;
}

std::vector<const PluginInfo*> PluginsUsed(
    const PipelineSpec& s, const Registry& reg,
    const std::map<std::string, std::vector<MeasRecord>>& files) {
  PluginUse use(reg);
  for (const auto& t : s.tasks) t->plugins_used(use);
  for (const auto& [path, records] : files)
    for (const auto& r : records) {
      use.increment(r.convention);
      use.increment(r.jacobian_convention);
    }
  return use.list();
}

}  // namespace imuconv::pipeline
