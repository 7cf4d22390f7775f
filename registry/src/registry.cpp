#include "imuconv/registry.h"

#include "builtin.h"
#include "imuconv/conversion.h"
#include "registry_impl.h"

namespace imuconv {

int BlockOffset(const BlockLabels& labels, std::string_view label) {
  for (int i = 0; i < kBlockCount; ++i)
    if (labels[i] != nullptr && label == labels[i]) return 3 * i;
  throw Error("unknown block label " + Quoted(label));
}

Registry::Registry() : impl_(std::make_unique<Impl>()) {
  auto ref = std::make_shared<const detail::PreintReferenceConvention>();
  PluginInfo info;
  info.id = ref->id();
  info.kind = PluginKind::IncrementConvention;
  info.file = "built-in";
  info.version = "1.0.0";
  info.summary = "reference chart for increments: dR Exp(dtheta), dp, dv, Delta b additive";
  const BlockLabels labels = ref->labels();
  info.blocks.assign(labels.begin(), labels.end());
  info.jacobian_convention = ref->jacobian_convention();
  info.analytic_jacobians = true;
  impl_->infos.push_back(info);
  impl_->increments.emplace(info.id, ref);
}

Registry::~Registry() = default;

const std::vector<PluginInfo>& Registry::plugins() const { return impl_->infos; }

const PluginInfo& Registry::info(PluginKind kind, std::string_view id) const {
  if (const PluginInfo* i = impl_->find(kind, id)) return *i;
  throw Error("no " + std::string(KindName(kind)) + " plugin with id " + Quoted(id) + " is loaded" +
              DidYouMean(id, ids(kind)) + "; known: " + KnownIds(ids(kind)));
}

bool Registry::has(PluginKind kind, std::string_view id) const {
  return impl_->find(kind, id) != nullptr;
}

std::vector<std::string> Registry::ids(PluginKind kind) const {
  std::vector<std::string> out;
  for (const auto& i : impl_->infos)
    if (i.kind == kind) out.push_back(i.id);
  return out;
}

std::shared_ptr<const StateConvention> Registry::state_convention(std::string_view id) const {
  return impl_->get(impl_->states, PluginKind::StateConvention, id);
}
std::shared_ptr<const IncrementConvention> Registry::increment_convention(
    std::string_view id) const {
  return impl_->get(impl_->increments, PluginKind::IncrementConvention, id);
}
std::shared_ptr<const Propagator> Registry::propagator(std::string_view id) const {
  return impl_->get(impl_->propagators, PluginKind::Propagator, id);
}
std::shared_ptr<const Preintegrator> Registry::preintegrator(std::string_view id) const {
  return impl_->get(impl_->preintegrators, PluginKind::Preintegrator, id);
}
std::shared_ptr<const ResidualFactor> Registry::residual_factor(std::string_view id) const {
  return impl_->get(impl_->residuals, PluginKind::Residual, id);
}

// ---- conversions by id (the work is in conversion.cpp) ------------------------------------

template <class Value>
Mat15 Registry::to_reference(std::string_view from, const Value& x) const {
  return ToReference(impl_->chart<Value>(from), x);
}
template <class Value>
Mat15 Registry::from_reference(std::string_view to, const Value& x) const {
  return FromReference(impl_->chart<Value>(to), x);
}
template <class Value>
Mat15 Registry::conversion(std::string_view from, std::string_view to, const Value& x) const {
  return Conversion(impl_->chart<Value>(from), impl_->chart<Value>(to), x);
}
template <class Value>
Mat15 Registry::convert_covariance(std::string_view from, std::string_view to, const Value& x,
                                   const Mat15& S) const {
  return ConvertCovariance(impl_->chart<Value>(from), impl_->chart<Value>(to), x, S);
}
template <class Value>
Mat15 Registry::convert_transition(std::string_view from, std::string_view to, const Value& x_s,
                                   const Value& x_e, const Mat15& Phi) const {
  return ConvertTransition(impl_->chart<Value>(from), impl_->chart<Value>(to), x_s, x_e, Phi);
}

IMUCONV_REGISTRY_CONVERSIONS(, ImuState)
IMUCONV_REGISTRY_CONVERSIONS(, PreintIncrement)

PropagationResult Registry::propagate(std::string_view propagator_id, std::string_view convention,
                                      const PropagationInput& in) const {
  const Propagator* prop = impl_->raw(impl_->propagators, PluginKind::Propagator, propagator_id);
  return PropagateIn(*prop, impl_->chart<ImuState>(prop->native_convention()),
                     impl_->chart<ImuState>(convention), in);
}

}  // namespace imuconv
