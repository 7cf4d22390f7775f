// Loading plugins: the search path, the directory scan and the checks at the boundary (the
// ABI handshake, the descriptor, the ids and strings a plugin returns, its charts).
#include <dlfcn.h>
#include <sys/stat.h>

#include <algorithm>
#include <boost/dll/runtime_symbol_info.hpp>
#include <boost/dll/shared_library.hpp>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <functional>
#include <set>

#include "convention_check.h"
#include "imuconv/plugin_kind.h"
#include "plugin_boundary.h"
#include "registry_impl.h"

namespace imuconv {
namespace fs = std::filesystem;

/// A plugin's four entry points, from a shared object or compiled in (plugin_kind.h).
struct Registry::EntryPoints {
  std::function<int()> abi;
  std::function<const PluginDescriptor*()> describe;
  std::function<void*()> create;
  std::function<void(void*)> destroy;
};

/// PluginInfo::file of a compiled-in plugin.
const char* const Registry::kCompiledIn = "compiled-in";

namespace {

std::vector<std::string> BlockVector(const BlockLabels& l) { return {l.begin(), l.end()}; }

// A second file declaring a (kind, id) already loaded. load_file reports it like any other
// error; load_directory and load_search_path make it fatal unless an override is allowed.
class DuplicateId : public Error {
 public:
  DuplicateId(PluginKind kind, const std::string& id, const std::string& first,
              const std::string& second)
      : Error("duplicate " + std::string(KindName(kind)) + " plugin id " + Quoted(id) + ": " +
              Quoted(first) + " (found first) and " + Quoted(second)),
        kind_(kind),
        id_(id),
        first_(first),
        second_(second) {}
  std::string override_message() const {
    return "duplicate " + std::string(KindName(kind_)) + " plugin id " + Quoted(id_) + ": " +
           Quoted(second_) + " is ignored and " + Quoted(first_) +
           ", earlier on the search path, is used (override allowed)";
  }

 private:
  PluginKind kind_;
  std::string id_, first_, second_;
};

// dlopen's own handle, held only while Boost.DLL opens the same object (so the reason for a
// failure comes from dlerror(), not Boost's generic "Bad file descriptor").
struct DlHandle {
  void* h = nullptr;
  ~DlHandle() {
    if (h) ::dlclose(h);
  }
};

std::string WithOverrideHint(const std::vector<std::string>& duplicates) {
  std::string msg = duplicates.size() == 1
                        ? duplicates[0]
                        : std::to_string(duplicates.size()) + " duplicate plugin ids:";
  if (duplicates.size() > 1)
    for (const auto& d : duplicates) msg += "\n" + d;
  return msg +
         "\nrefusing to choose between two plugins with one id: remove one, or allow the override "
         "(imuconv: --allow-plugin-override; a pipeline: \"allow_plugin_override\": true) to use "
         "the one "
         "earlier on the search path";
}

// Loads every imuconv_plugin_*.so in dir into reg. Failures become issues; duplicate ids are
// issues with an override, else collected in `duplicates` for the caller to throw.
/// One plugin of a search path, loaded by `load`: a failure becomes a LoadIssue, a duplicate
/// id an override warning or a fatal duplicate, as LoadOptions says.
template <typename Load>
void LoadOne(const std::string& what, const LoadOptions& options, std::vector<LoadIssue>& issues,
             std::vector<std::string>& duplicates, const Load& load) {
  try {
    load();
  } catch (const DuplicateId& d) {
    if (options.allow_override)
      issues.push_back({what, d.override_message(), true});
    else
      duplicates.push_back(d.what());
  } catch (const std::exception& e) {
    issues.push_back({what, e.what()});
  } catch (...) {
    issues.push_back({what, "failed to load with an exception that is not a std::exception"});
  }
}

void ScanDirectory(Registry& reg, const std::string& dir, const LoadOptions& options,
                   std::vector<LoadIssue>& issues, std::vector<std::string>& duplicates) {
  std::error_code ec;
  const fs::file_status st = fs::status(dir, ec);
  if (st.type() == fs::file_type::not_found) {
    issues.push_back({dir, "plugin directory does not exist"});
    return;
  }
  if (ec) {
    issues.push_back({dir, "cannot access plugin directory: " + ec.message()});
    return;
  }
  if (!fs::is_directory(st)) {
    issues.push_back({dir, "plugin directory is not a directory"});
    return;
  }
  std::vector<std::string> files;
  fs::directory_iterator it(dir, ec);
  if (ec) {
    issues.push_back({dir, "cannot list plugin directory: " + ec.message()});
    return;
  }
  for (const fs::directory_iterator end{}; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (name.size() > 3 && name.rfind("imuconv_plugin_", 0) == 0 &&
        name.compare(name.size() - 3, 3, ".so") == 0)
      files.push_back(it->path().string());
  }
  if (ec) issues.push_back({dir, "listing the plugin directory stopped early: " + ec.message()});
  std::sort(files.begin(), files.end());  // deterministic order
  for (const auto& f : files) LoadOne(f, options, issues, duplicates, [&] { reg.load_file(f); });
}

}  // namespace

void Registry::load_file(const std::string& path) {
  const std::string where = Quoted(path);
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0 && errno == ENOENT)
    throw Error("plugin file " + where + " does not exist");
  if (const std::string why = detail::NotASharedObject(path); !why.empty())
    throw Error("cannot load " + where + ": it " + why);
  // One file is one identity (device, inode), whatever path or link names it.
  const std::pair<dev_t, ino_t> identity(st.st_dev, st.st_ino);
  if (auto it = impl_->loaded_files.find(identity); it != impl_->loaded_files.end())
    throw Error("plugin file " + where + " is already loaded (as " + Quoted(it->second) + ")");

  // Absolute, so that dlopen never searches the library path for a bare file name.
  std::error_code fec;
  const std::string abs = fs::absolute(path, fec).string();
  DlHandle probe;
  ::dlerror();
  probe.h = ::dlopen(abs.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (probe.h == nullptr) {
    const char* why = ::dlerror();
    throw Error("cannot load " + where +
                " as a shared library: " + Printable(why ? why : "dlopen failed"));
  }
  auto lib = std::make_shared<boost::dll::shared_library>();
  boost::dll::fs::error_code ec;
  lib->load(abs, boost::dll::load_mode::rtld_now | boost::dll::load_mode::rtld_local, ec);
  if (ec || !lib->is_loaded())
    throw Error("cannot load " + where +
                " as a shared library: " + (ec ? ec.message() : "unknown error"));
  for (const char* sym : {"imuconv_plugin_abi", "imuconv_plugin_describe", "imuconv_plugin_create",
                          "imuconv_plugin_destroy"}) {
    if (!lib->has(sym))
      throw Error(where + " is not an imuconv plugin: it does not export '" + sym + "'");
  }
  // The entry points are fetched without noexcept: one that throws anyway is caught by
  // CallPlugin and named, instead of reaching std::terminate through a noexcept call. The
  // library stays loaded while any object created from it lives (the destroy function holds it).
  EntryPoints e;
  e.abi = [lib] { return lib->get_alias<int()>("imuconv_plugin_abi")(); };
  e.describe = [lib] {
    return lib->get_alias<const PluginDescriptor*()>("imuconv_plugin_describe")();
  };
  e.create = [lib] { return lib->get_alias<void*()>("imuconv_plugin_create")(); };
  auto destroy = lib->get_alias<void(void*)>("imuconv_plugin_destroy");
  e.destroy = [lib, destroy](void* p) { destroy(p); };
  adopt(path, e);
  impl_->loaded_files.emplace(identity, path);
}

void Registry::adopt_compiled_in(std::size_t k) {
  const detail::CompiledInPlugin plugin = detail::CompiledInPlugins().at(k);
  EntryPoints e;
  e.abi = [plugin] { return plugin.abi(); };
  e.describe = [plugin] { return plugin.describe(); };
  e.create = [plugin] { return plugin.create(); };
  e.destroy = [plugin](void* p) { plugin.destroy(p); };
  adopt(kCompiledIn, e);
}

void Registry::load_compiled_in() {
  const std::size_t n = detail::CompiledInPlugins().size();
  while (impl_->compiled_in_adopted < n) adopt_compiled_in(impl_->compiled_in_adopted++);
}

bool Registry::has_compiled_in() { return !detail::CompiledInPlugins().empty(); }

void Registry::adopt(const std::string& path, const EntryPoints& e) {
  const std::string where = Quoted(path);
  // 1. ABI handshake before anything else is called.
  const int abi = detail::CallPlugin(path, "imuconv_plugin_abi()", e.abi);
  if (abi != kPluginAbiVersion)
    throw Error(where + " was built for imuconv plugin ABI version " + std::to_string(abi) +
                "; this imuconv speaks version " + std::to_string(kPluginAbiVersion) +
                ": rebuild the plugin");
  const PluginDescriptor* d = detail::CallPlugin(path, "imuconv_plugin_describe()", e.describe);
  if (d == nullptr) throw Error(where + " returned no plugin descriptor");
  const AbiFingerprint want;
  const AbiFingerprint& got = d->fingerprint;
  if (got.abi_version != want.abi_version ||
      got.eigen_max_static_align != want.eigen_max_static_align ||
      got.sizeof_state != want.sizeof_state || got.sizeof_window != want.sizeof_window ||
      got.gnu_major != want.gnu_major || got.cxx_abi != want.cxx_abi)
    throw Error(where + " has an incompatible binary layout (Eigen alignment " +
                std::to_string(got.eigen_max_static_align) + " vs " +
                std::to_string(want.eigen_max_static_align) + ", ImuState size " +
                std::to_string(got.sizeof_state) + " vs " + std::to_string(want.sizeof_state) +
                ", g++ " + std::to_string(got.gnu_major) + " vs " + std::to_string(want.gnu_major) +
                "): rebuild it with the same compiler and flags as imuconv");
  const int kind_value = static_cast<int>(d->kind);
  if (kind_value < 1 || kind_value > static_cast<int>(PluginKind::Residual))
    throw Error(where + " declares an unknown plugin kind " + std::to_string(kind_value));
  if (const std::string why = detail::IdProblem(d->id); !why.empty())
    throw Error("plugin " + where + ": its descriptor's id " + why);
  const std::string id = d->id;
  if (const std::string why = detail::TextProblem(d->version); !why.empty())
    throw Error("plugin " + where + " (" + Quoted(id) + "): its descriptor's version " + why +
                " (expected a UTF-8 string such as \"1.0.0\")");
  if (const std::string why = detail::TextProblem(d->summary); !why.empty())
    throw Error("plugin " + where + " (" + Quoted(id) + "): its descriptor's summary " + why +
                " (expected a one-line UTF-8 description)");
  if (const PluginInfo* other = impl_->find(d->kind, id))
    throw DuplicateId(d->kind, id, other->file, path);

  // 2. Create inside the plugin; destroy inside the plugin; the deleter keeps it alive.
  void* raw = detail::CallPlugin(path, "imuconv_plugin_create()", e.create);
  if (raw == nullptr) throw Error(where + " failed to create its " + Quoted(id) + " object");

  PluginInfo info;
  info.id = id;
  info.kind = d->kind;
  info.file = path;
  info.version = d->version;
  info.summary = d->summary;

  auto wrap = [&](auto* typed) {
    using T = std::remove_pointer_t<decltype(typed)>;
    return std::shared_ptr<const T>(typed, [destroy = e.destroy](const T* p) {
      // A destroy() that throws has no one left to tell (this runs in a destructor); the
      // object may leak, the host carries on.
      try {
        destroy(const_cast<T*>(p));
      } catch (...) {
      }
    });
  };
  auto id_check = [&](const char* got_id) {
    if (got_id == nullptr)
      throw Error("plugin " + where + ": id() returned a null pointer (expected " + Quoted(id) +
                  ")");
    const std::string_view got_view(got_id, strnlen(got_id, detail::kMaxPluginIdLength + 1));
    if (got_view != id)
      throw Error("plugin " + where + ": object id " + Quoted(got_view) +
                  " differs from the descriptor's id " + Quoted(id));
  };
  // An id naming another plugin (a convention), returned by the object.
  auto ref_id = [&](const char* got, const char* what) -> std::string {
    if (const std::string why = detail::IdProblem(got); !why.empty())
      throw Error("plugin " + where + " (" + Quoted(id) + "): " + what + " " + why);
    return got;
  };

  // Any object: owned with the plugin's destroy(), then its id checked against the
  // descriptor's.
  auto adopt = [&](auto* typed) {
    auto obj = wrap(typed);
    id_check(obj->id());
    return obj;
  };
  // A convention of either kind: checked against its reference chart, then kept.
  auto adopt_chart = [&](auto* typed, const char* what) {
    auto obj = adopt(typed);
    bool analytic = false;
    const std::string err = detail::CheckConvention(*obj, &analytic);
    if (!err.empty())
      throw Error(std::string(what) + " " + Quoted(id) + " in " + where + " is refused: " + err);
    info.blocks = BlockVector(obj->labels());
    info.analytic_jacobians = analytic;
    return obj;
  };
  switch (d->kind) {
    case PluginKind::StateConvention:
      impl_->states.emplace(id,
                            adopt_chart(static_cast<StateConvention*>(raw), "state convention"));
      break;
    case PluginKind::IncrementConvention: {
      auto obj = adopt_chart(static_cast<IncrementConvention*>(raw), "increment convention");
      info.jacobian_convention = ref_id(obj->jacobian_convention(), "jacobian_convention()");
      impl_->increments.emplace(id, obj);
      break;
    }
    case PluginKind::Propagator: {
      auto obj = adopt(static_cast<Propagator*>(raw));
      info.native_convention = ref_id(obj->native_convention(), "native_convention()");
      impl_->propagators.emplace(id, obj);
      break;
    }
    case PluginKind::Preintegrator: {
      auto obj = adopt(static_cast<Preintegrator*>(raw));
      info.native_convention = ref_id(obj->cov_convention(), "cov_convention()");
      info.jacobian_convention = ref_id(obj->jacobian_convention(), "jacobian_convention()");
      impl_->preintegrators.emplace(id, obj);
      break;
    }
    case PluginKind::Residual: {
      auto obj = adopt(static_cast<ResidualFactor*>(raw));
      // "gtsam" and "forster" name the registry's generic residuals (bridge.h, ResidualKind),
      // which the residual task and the Python module resolve before any plugin.
      if (id == "gtsam" || id == "forster")
        throw Error("plugin " + where + ": residual id " + Quoted(id) +
                    " is taken by the registry's generic residual of that name (bridge.h); "
                    "choose another id");
      info.native_convention = ref_id(obj->increment_convention(), "increment_convention()");
      const char* layout = obj->layout();
      if (const std::string why = detail::TextProblem(layout); !why.empty())
        throw Error("plugin " + where + " (" + Quoted(id) + "): layout() " + why +
                    " (expected a UTF-8 description of its numbers)");
      info.layout = layout;
      // Bounded so that a chi-square quantile of it stays meaningful and cheap.
      const int dof = obj->degrees_of_freedom();
      if (dof < 1 || dof > 1000)
        throw Error("plugin " + where + " (" + Quoted(id) + "): degrees_of_freedom() is " +
                    std::to_string(dof) + " (expected 1 to 1000, the residual's dimension)");
      info.degrees_of_freedom = dof;
      impl_->residuals.emplace(id, obj);
      break;
    }
  }
  impl_->infos.push_back(std::move(info));
}

std::vector<LoadIssue> Registry::load_directory(const std::string& dir,
                                                const LoadOptions& options) {
  std::vector<LoadIssue> issues;
  std::vector<std::string> duplicates;
  ScanDirectory(*this, dir, options, issues, duplicates);
  if (!duplicates.empty()) throw Error(WithOverrideHint(duplicates));
  return issues;
}

std::string Registry::default_plugin_dir() {
  boost::dll::fs::error_code ec;
  const fs::path here = boost::dll::this_line_location(ec);
  if (!ec) {
    const fs::path installed = here.parent_path() / IMUCONV_PLUGIN_SUBDIR;
    std::error_code fec;
    if (fs::is_directory(installed, fec)) return installed.string();
  }
  return IMUCONV_BUILD_PLUGIN_DIR;
}

std::vector<std::string> Registry::search_path(const std::vector<std::string>& extra_dirs) {
  std::vector<std::string> dirs = extra_dirs;
  if (const char* env = std::getenv("IMUCONV_PLUGIN_PATH")) {
    std::string s = env;
    std::size_t start = 0;
    while (start <= s.size()) {
      const std::size_t colon = s.find(':', start);
      const std::string part =
          s.substr(start, colon == std::string::npos ? std::string::npos : colon - start);
      if (!part.empty()) dirs.push_back(part);
      if (colon == std::string::npos) break;
      start = colon + 1;
    }
  }
  dirs.push_back(default_plugin_dir());
  // The same directory named twice is searched once.
  std::vector<std::string> unique;
  std::set<std::string> seen;
  for (const auto& d : dirs) {
    std::error_code ec;
    const std::string key = fs::weakly_canonical(d, ec).string();
    if (seen.insert(ec ? d : key).second) unique.push_back(d);
  }
  return unique;
}

std::vector<LoadIssue> Registry::load_search_path(const std::vector<std::string>& extra_dirs,
                                                  const LoadOptions& options) {
  std::vector<LoadIssue> issues;
  std::vector<std::string> duplicates;
  // With compiled-in plugins (IMUCONV_STATIC_PLUGINS), they take the built-in directory's place.
  std::error_code ec;
  const std::string builtin = fs::weakly_canonical(default_plugin_dir(), ec).string();
  for (const auto& dir : search_path(extra_dirs)) {
    std::error_code dec;
    if (has_compiled_in() && fs::weakly_canonical(dir, dec).string() == builtin) {
      const std::size_t n = detail::CompiledInPlugins().size();
      while (impl_->compiled_in_adopted < n) {
        const std::size_t k = impl_->compiled_in_adopted++;
        LoadOne(kCompiledIn, options, issues, duplicates, [&] { adopt_compiled_in(k); });
      }
      continue;
    }
    ScanDirectory(*this, dir, options, issues, duplicates);
  }
  if (!duplicates.empty()) throw Error(WithOverrideHint(duplicates));
  return issues;
}

}  // namespace imuconv
