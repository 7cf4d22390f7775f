// The plugin ABI: what every imuconv plugin shared object exports through Boost.DLL
// (CMake target imuconv::plugin_abi; the layout facts are in plugin_kind.h).
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
#include <type_traits>

#include "imuconv/plugin_kind.h"

namespace imuconv::detail {

/// The object a plugin creates: IMPL with id() returning the id the IMUCONV_PLUGIN line
/// declares, so that the id is written once. A final IMPL (which must then return that id
/// itself; the host checks) is used as it is.
template <class Impl, const char* Id, bool = std::is_final_v<Impl>>
struct PluginObject final : Impl {
  const char* id() const noexcept override { return Id; }
};
template <class Impl, const char* Id>
struct PluginObject<Impl, Id, true> {};
template <class Impl, const char* Id>
using PluginObjectT = std::conditional_t<std::is_final_v<Impl>, Impl, PluginObject<Impl, Id>>;

}  // namespace imuconv::detail

// The entry points of one plugin (internal to IMUCONV_PLUGIN).
#define IMUCONV_PLUGIN_ENTRY_POINTS_(KIND, IMPL, ID, VERSION, SUMMARY)                    \
  namespace imuconv_plugin_entry {                                                        \
  using Base = ::imuconv::PluginBase<::imuconv::PluginKind::KIND>::type;                  \
  constexpr char kId[] = ID;                                                              \
  using Object = ::imuconv::detail::PluginObjectT<IMPL, kId>;                             \
  int abi() noexcept { return ::imuconv::kPluginAbiVersion; }                             \
  const ::imuconv::PluginDescriptor* describe() noexcept {                                \
    static const ::imuconv::PluginDescriptor d{                                           \
        ::imuconv::AbiFingerprint{}, ::imuconv::PluginKind::KIND, kId, VERSION, SUMMARY}; \
    return &d;                                                                            \
  }                                                                                       \
  void* create() noexcept {                                                               \
    try {                                                                                 \
      Base* b = new Object();                                                             \
      return static_cast<void*>(b);                                                       \
    } catch (...) {                                                                       \
      return nullptr;                                                                     \
    }                                                                                     \
  }                                                                                       \
  void destroy(void* p) noexcept { delete static_cast<Base*>(p); }                        \
  }

/// Defines and exports one plugin. Use once per plugin source file, at global scope:
///   IMUCONV_PLUGIN(StateConvention, MyConvention, "my_id", "1.0.0", "one line summary")
/// The id is declared here only: MyConvention leaves id() to this line. Compiled with
/// IMUCONV_PLUGIN_STATIC defined, the same file adds the plugin to the process's table of
/// compiled-in plugins instead of exporting it (IMUCONV_STATIC_PLUGINS builds the built-in
/// plugins into the registry library that way); the entry points are then internal, so many
/// plugins link into one library.
#if defined(IMUCONV_PLUGIN_STATIC)
#define IMUCONV_PLUGIN(KIND, IMPL, ID, VERSION, SUMMARY)                                           \
  namespace {                                                                                      \
  IMUCONV_PLUGIN_ENTRY_POINTS_(KIND, IMPL, ID, VERSION, SUMMARY)                                   \
  [[maybe_unused]] const bool imuconv_plugin_added = ::imuconv::detail::AddCompiledInPlugin(       \
      {&imuconv_plugin_entry::abi, &imuconv_plugin_entry::describe, &imuconv_plugin_entry::create, \
       &imuconv_plugin_entry::destroy});                                                           \
  }
#else
#define IMUCONV_PLUGIN(KIND, IMPL, ID, VERSION, SUMMARY)                   \
  IMUCONV_PLUGIN_ENTRY_POINTS_(KIND, IMPL, ID, VERSION, SUMMARY)           \
  BOOST_DLL_ALIAS(imuconv_plugin_entry::abi, imuconv_plugin_abi)           \
  BOOST_DLL_ALIAS(imuconv_plugin_entry::describe, imuconv_plugin_describe) \
  BOOST_DLL_ALIAS(imuconv_plugin_entry::create, imuconv_plugin_create)     \
  BOOST_DLL_ALIAS(imuconv_plugin_entry::destroy, imuconv_plugin_destroy)
#endif
