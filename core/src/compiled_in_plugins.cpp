// The process's table of compiled-in plugins (plugin_abi.h, IMUCONV_PLUGIN_STATIC): filled by
// the plugins' static initialisers, read by Registry::load_compiled_in. Function-local, so
// that it exists before any initialiser of another translation unit adds to it.
#include <vector>

#include "imuconv/plugin_kind.h"

namespace imuconv::detail {
namespace {
std::vector<CompiledInPlugin>& Table() noexcept {
  static std::vector<CompiledInPlugin> table;
  return table;
}
}  // namespace

bool AddCompiledInPlugin(const CompiledInPlugin& plugin) noexcept {
  try {
    Table().push_back(plugin);
  } catch (...) {  // out of memory at static initialisation: the plugin is not listed
  }
  return true;
}

const std::vector<CompiledInPlugin>& CompiledInPlugins() noexcept { return Table(); }

}  // namespace imuconv::detail
