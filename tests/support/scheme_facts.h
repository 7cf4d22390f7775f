// What the declared facts of a scheme (a propagator or a preintegrator: noise_simulation_facts.h,
// increment_mean_facts.h) share: the scheme's plugin by its kind, and the shared test of one
// kind of fact over the test registry's plugins of that kind.
#pragma once

#include <string>

#include "declared_facts.h"
#include "imuconv/plugin_kind.h"
#include "imuconv_test.h"

namespace imuconv::test {

/// The test registry's plugin `id` of the scheme kind kKind (Propagator or Preintegrator).
template <PluginKind kKind>
auto SchemePlugin(const std::string& id) {
  static_assert(kKind == PluginKind::Propagator || kKind == PluginKind::Preintegrator);
  if constexpr (kKind == PluginKind::Propagator)
    return Plugins().propagator(id);
  else
    return Plugins().preintegrator(id);
}

/// DeclaredFacts<Of<kKind>>::CheckAll on the test registry: `check_one(id, facts)` for every
/// declaration, and a declaration for every loaded scheme of the kind, whose missing line reads
/// MACRO(<kind>, <id>, ARGS) (`macro` and `args` as given).
template <template <PluginKind> class Of, PluginKind kKind, typename CheckOne>
void CheckSchemeDeclarations(const char* where, const char* macro, const char* args,
                             CheckOne check_one) {
  static_assert(kKind == PluginKind::Propagator || kKind == PluginKind::Preintegrator);
  DeclaredFacts<Of<kKind>>::CheckAll(
      Plugins(), kKind, where,
      std::string(macro) + "(" + SchemeKindName(kKind) + ", <id>, " + args + ")", check_one);
}

}  // namespace imuconv::test
