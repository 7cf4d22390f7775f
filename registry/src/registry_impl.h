// The registry's state: every loaded plugin by kind and id, and the lookups written once for
// all kinds (a chart's kind follows from its value type).
#pragma once

#include <sys/types.h>

#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include "imuconv/did_you_mean.h"
#include "imuconv/printable.h"
#include "imuconv/registry.h"

namespace imuconv {

template <typename T>
using IdMap = std::map<std::string, std::shared_ptr<const T>, std::less<>>;

/// The plugin kind of a convention over Value.
template <class Value>
constexpr PluginKind ChartKind() {
  return std::is_same_v<Value, ImuState> ? PluginKind::StateConvention
                                         : PluginKind::IncrementConvention;
}

inline std::string KnownIds(const std::vector<std::string>& ids) {
  std::string s;
  for (const auto& id : ids) s += (s.empty() ? "" : ", ") + id;
  return s.empty() ? "(none loaded)" : s;
}

struct Registry::Impl {
  std::vector<PluginInfo> infos;
  IdMap<StateConvention> states;
  IdMap<IncrementConvention> increments;
  IdMap<Propagator> propagators;
  IdMap<Preintegrator> preintegrators;
  IdMap<ResidualFactor> residuals;
  std::map<std::pair<dev_t, ino_t>, std::string> loaded_files;  // identity -> path it was loaded as
  std::size_t compiled_in_adopted = 0;  // entries of detail::CompiledInPlugins() adopted

  template <class Value>
  IdMap<Chart<Value>>& charts() {
    if constexpr (std::is_same_v<Value, ImuState>)
      return states;
    else
      return increments;
  }
  template <class Value>
  const IdMap<Chart<Value>>& charts() const {
    return const_cast<Impl*>(this)->charts<Value>();
  }

  const PluginInfo* find(PluginKind kind, std::string_view id) const {
    for (const auto& i : infos)
      if (i.kind == kind && i.id == id) return &i;
    return nullptr;
  }

  /// The plugin `id` of `kind`; throws Error listing the known ids when there is none.
  template <typename T>
  std::shared_ptr<const T> get(const IdMap<T>& m, PluginKind kind, std::string_view id) const {
    auto it = m.find(id);
    if (it != m.end()) return it->second;
    std::vector<std::string> known;
    for (const auto& [k, v] : m) known.push_back(k);
    throw Error("no " + std::string(KindName(kind)) + " plugin with id " + Quoted(id) +
                " is loaded" + DidYouMean(id, known) + "; known: " + KnownIds(known));
  }
  /// get() without the shared_ptr copy, for the conversions on the hot path.
  template <typename T>
  const T* raw(const IdMap<T>& m, PluginKind kind, std::string_view id) const {
    auto it = m.find(id);
    if (it != m.end()) return it->second.get();
    return get(m, kind, id).get();
  }
  template <class Value>
  const Chart<Value>& chart(std::string_view id) const {
    return *raw(charts<Value>(), ChartKind<Value>(), id);
  }
};

}  // namespace imuconv
