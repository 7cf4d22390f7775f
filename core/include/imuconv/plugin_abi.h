// The plugin ABI: what every imuconv plugin shared object exports through Boost.DLL.
//
// Each plugin exports four aliases (BOOST_DLL_ALIAS):
//   imuconv_plugin_abi      int() noexcept                    -> kPluginAbiVersion
//   imuconv_plugin_describe const PluginDescriptor*() noexcept
//   imuconv_plugin_create   void*() noexcept   (a pointer to the kind's base class, or null)
//   imuconv_plugin_destroy  void(void*) noexcept
// The host checks the ABI version first, then the descriptor's layout fields, and only then
// creates anything. Objects are created and destroyed inside the plugin; the host's handle
// keeps the shared library loaded for as long as the object lives. Nothing throws across.
#pragma once

#include <boost/config.hpp>
#include <boost/dll/alias.hpp>
#include <new>

#include "imuconv/error_state.h"
#include "imuconv/preintegrator.h"
#include "imuconv/propagator.h"

namespace imuconv {

/// Bumped whenever a base class, value type or this descriptor changes layout.
constexpr int kPluginAbiVersion = 1;

enum class PluginKind : int {
  StateConvention = 1,   ///< ErrorState
  PreintConvention = 2,  ///< PreintConvention
  Propagator = 3,        ///< Propagator
  Preintegrator = 4,     ///< Preintegrator
};

inline const char* KindName(PluginKind k) noexcept {
  switch (k) {
    case PluginKind::StateConvention: return "state_convention";
    case PluginKind::PreintConvention: return "preint_convention";
    case PluginKind::Propagator: return "propagator";
    case PluginKind::Preintegrator: return "preintegrator";
  }
  return "unknown";
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

template <PluginKind K> struct PluginBase;
template <> struct PluginBase<PluginKind::StateConvention> { using type = ErrorState; };
template <> struct PluginBase<PluginKind::PreintConvention> { using type = PreintConvention; };
template <> struct PluginBase<PluginKind::Propagator> { using type = Propagator; };
template <> struct PluginBase<PluginKind::Preintegrator> { using type = Preintegrator; };

}  // namespace imuconv

/// Defines and exports one plugin. Use once per plugin source file, at global scope:
///   IMUCONV_PLUGIN(StateConvention, MyConvention, "my_id", "1.0.0", "one line summary")
/// The plugin's id() must return the same id.
#define IMUCONV_PLUGIN(KIND, IMPL, ID, VERSION, SUMMARY)                                      \
  namespace imuconv_plugin_entry {                                                            \
  using Base = ::imuconv::PluginBase<::imuconv::PluginKind::KIND>::type;                      \
  int abi() noexcept { return ::imuconv::kPluginAbiVersion; }                                 \
  const ::imuconv::PluginDescriptor* describe() noexcept {                                    \
    static const ::imuconv::PluginDescriptor d{::imuconv::AbiFingerprint{},                   \
                                               ::imuconv::PluginKind::KIND, ID, VERSION,      \
                                               SUMMARY};                                      \
    return &d;                                                                                \
  }                                                                                           \
  void* create() noexcept {                                                                   \
    try {                                                                                     \
      Base* b = new IMPL();                                                                   \
      return static_cast<void*>(b);                                                           \
    } catch (...) {                                                                           \
      return nullptr;                                                                         \
    }                                                                                         \
  }                                                                                           \
  void destroy(void* p) noexcept { delete static_cast<Base*>(p); }                            \
  }                                                                                           \
  BOOST_DLL_ALIAS(imuconv_plugin_entry::abi, imuconv_plugin_abi)                              \
  BOOST_DLL_ALIAS(imuconv_plugin_entry::describe, imuconv_plugin_describe)                    \
  BOOST_DLL_ALIAS(imuconv_plugin_entry::create, imuconv_plugin_create)                        \
  BOOST_DLL_ALIAS(imuconv_plugin_entry::destroy, imuconv_plugin_destroy)
