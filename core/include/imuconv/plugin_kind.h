// What the host and a plugin agree on before any object crosses: the ABI version, the kinds
// of plugin and the descriptor each plugin exports. Free of Boost, so that the registry's
// public header can name a PluginKind without making Boost.DLL everyone's dependency (the
// exporting side is plugin_abi.h, target imuconv::plugin_abi).
#pragma once

#include <cstddef>
#include <iterator>
#include <tuple>
#include <vector>

#include "imuconv/chart.h"
#include "imuconv/enum_name.h"
#include "imuconv/export.h"
#include "imuconv/preintegrator.h"
#include "imuconv/propagator.h"
#include "imuconv/residual_factor.h"
#include "imuconv/types.h"
#include "imuconv/window.h"

namespace imuconv {

/// Bumped whenever a base class, value type or the descriptor changes layout. 2: the two
/// convention interfaces became Chart<Value> (order(), J_ref_this, J_this_ref,
/// jacobian_convention()). 3: Propagator and Preintegrator gained the optional
/// increment_mean() and noise_simulation() (increment_mean.h, noise_simulation.h). The kind
/// Residual (residual_factor.h) came without a bump: it adds a base class and changes none,
/// so every plugin of version 3 loads as before, and a host that predates the kind refuses a
/// residual plugin by its unknown kind value. 4: ResidualFactor gained cost_spec()
/// (residual_cost_spec.h), a new virtual function: a residual plugin of version 3 has a shorter
/// vtable, so every plugin of version 3 is refused by its version.
constexpr int kPluginAbiVersion = 4;

enum class PluginKind : int {
  StateConvention = 1,      ///< StateConvention (Chart<ImuState>)
  IncrementConvention = 2,  ///< IncrementConvention (Chart<PreintIncrement>)
  Propagator = 3,           ///< Propagator
  Preintegrator = 4,        ///< Preintegrator
  Residual = 5,             ///< ResidualFactor (residual_factor.h)
};

/// Every kind, in the order listings show them.
inline constexpr PluginKind kPluginKinds[] = {
    PluginKind::StateConvention, PluginKind::IncrementConvention, PluginKind::Propagator,
    PluginKind::Preintegrator, PluginKind::Residual};

/// The kind's name in messages and outputs. An increment convention is "preint_convention"
/// there: the name is part of the output format (plugins_used, `imuconv plugins`). "unknown"
/// for a value that is no kind (a hostile plugin's descriptor).
inline const char* KindName(PluginKind k) noexcept {
  static constexpr const char* kNames[] = {"state_convention", "preint_convention", "propagator",
                                           "preintegrator", "residual"};  // from kind 1 on
  static_assert(std::size(kNames) == std::size(kPluginKinds), "a name per kind");
  return EnumName(k, PluginKind::StateConvention, kNames, "unknown");
}

/// Layout facts both sides must agree on before any object crosses the boundary.
struct AbiFingerprint {
  int abi_version = kPluginAbiVersion;
  int eigen_max_static_align = EIGEN_MAX_STATIC_ALIGN_BYTES;
  int sizeof_state = static_cast<int>(sizeof(ImuState));
  int sizeof_window = static_cast<int>(sizeof(SampleWindow));
  int gnu_major = __GNUC__;
  int cxx_abi = _GLIBCXX_USE_CXX11_ABI;
};

struct PluginDescriptor {
  AbiFingerprint fingerprint;
  PluginKind kind;
  const char* id;
  const char* version;
  const char* summary;
};

/// The base class a plugin of kind K derives from: the kinds' base classes in kind order,
/// from kind 1 on (as KindName's names).
using PluginBases =
    std::tuple<StateConvention, IncrementConvention, Propagator, Preintegrator, ResidualFactor>;
static_assert(std::tuple_size_v<PluginBases> == std::size(kPluginKinds), "a base class per kind");
template <PluginKind K>
struct PluginBase {
  using type = std::tuple_element_t<static_cast<std::size_t>(K) - 1, PluginBases>;
};

namespace detail {

/// The four entry points of one plugin compiled into a program or library instead of a shared
/// object (IMUCONV_PLUGIN_STATIC): the registry adopts them as it adopts a file's, with the
/// same checks (Registry::load_compiled_in).
struct CompiledInPlugin {
  int (*abi)() noexcept;
  const PluginDescriptor* (*describe)() noexcept;
  void* (*create)() noexcept;
  void (*destroy)(void*) noexcept;
};
/// Adds a compiled-in plugin to the process's table (at static initialisation); always true.
IMUCONV_API bool AddCompiledInPlugin(const CompiledInPlugin& plugin) noexcept;
/// The table, in the order the plugins were added.
IMUCONV_API const std::vector<CompiledInPlugin>& CompiledInPlugins() noexcept;

}  // namespace detail

}  // namespace imuconv
