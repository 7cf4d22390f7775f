#include "imuconv/registry.h"

#include <dlfcn.h>
#include <sys/stat.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <boost/dll/runtime_symbol_info.hpp>
#include <boost/dll/shared_library.hpp>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <random>
#include <set>
#include <sstream>

#include "builtin.h"
#include "plugin_boundary.h"
#include "imuconv/conversion.h"
#include "imuconv/numeric.h"
#include "imuconv/reference_charts.h"
#include "imuconv/so3.h"

namespace imuconv {
namespace fs = std::filesystem;

namespace {

// Gate for a plugin's analytic Jacobian against Ridders' differences: far above the
// ~1e-10 the differences reach on these smooth charts, far below any real mistake (a
// wrong sign, block or transpose shows up at O(1)).
constexpr double kJacobianCheckTol = 1e-7;
// Gate for local(x, retract(x, d)) = d: a chart that is a true inverse reaches ~1e-15.
constexpr double kRoundTripTol = 1e-9;

template <typename T>
using IdMap = std::map<std::string, std::shared_ptr<const T>, std::less<>>;

std::string KnownIds(const std::vector<std::string>& ids) {
  std::string s;
  for (const auto& id : ids) s += (s.empty() ? "" : ", ") + id;
  return s.empty() ? "(none loaded)" : s;
}

std::string FormatMax(double v) {
  std::ostringstream o;
  o.precision(3);
  o << v;
  return o.str();
}

// Sample points for the load-time checks: identity, tiny and random (fixed seed).
std::vector<ImuState> CheckStates() {
  std::vector<ImuState> xs(3);
  xs[1].R = so3::Exp(Vec3(1e-7, -2e-7, 3e-7));
  xs[1].p = Vec3(1e-6, 2e-6, -1e-6);
  xs[1].v = Vec3(-1e-6, 1e-6, 2e-6);
  xs[1].bg = Vec3(1e-7, 0, -1e-7);
  xs[1].ba = Vec3(0, 1e-6, 1e-6);
  std::mt19937 rng(12345);
  std::normal_distribution<double> n(0.0, 1.0);
  auto rv = [&](double s) { return Vec3(s * n(rng), s * n(rng), s * n(rng)); };
  xs[2].R = so3::Exp(rv(1.0));
  xs[2].p = rv(10.0);
  xs[2].v = rv(2.0);
  xs[2].bg = rv(0.01);
  xs[2].ba = rv(0.1);
  return xs;
}

std::vector<PreintIncrement> CheckIncrements() {
  std::vector<PreintIncrement> xs(3);
  xs[1].dR = so3::Exp(Vec3(1e-7, -2e-7, 3e-7));
  xs[1].dp = Vec3(1e-6, 2e-6, -1e-6);
  xs[1].dv = Vec3(-1e-6, 1e-6, 2e-6);
  std::mt19937 rng(54321);
  std::normal_distribution<double> n(0.0, 1.0);
  auto rv = [&](double s) { return Vec3(s * n(rng), s * n(rng), s * n(rng)); };
  xs[2].dR = so3::Exp(rv(0.7));
  xs[2].dp = rv(10.0);
  xs[2].dv = rv(3.0);
  xs[2].dbg = rv(1e-3);
  xs[2].dba = rv(1e-2);
  return xs;
}

std::vector<Vec15> CheckDeltas() {
  std::mt19937 rng(777);
  std::normal_distribution<double> n(0.0, 1.0);
  std::vector<Vec15> ds;
  ds.push_back(Vec15::Zero());
  for (double s : {1e-6, 1e-2, 0.3}) {
    Vec15 d;
    for (int i = 0; i < 15; ++i) d[i] = s * n(rng);
    ds.push_back(d);
  }
  return ds;
}

std::string CheckLabels(const BlockLabels& labels) {
  const std::set<std::string> want{"p", "theta", "v", "bg", "ba"};
  std::set<std::string> got;
  for (const char* l : labels) {
    if (l == nullptr) return "a block label is null";
    got.insert(l);
  }
  if (got != want) return "block labels must be a permutation of p, theta, v, bg, ba";
  return {};
}

// Checks one convention (state or increment) against its reference chart. Returns an
// empty string when it passes, else what failed.
template <typename Conv, typename Value, typename RefRetract, typename RefLocal>
std::string CheckConvention(const Conv& c, const std::vector<Value>& xs, RefRetract ref_retract,
                            RefLocal ref_local, bool* analytic) {
  if (std::string e = CheckLabels(c.labels()); !e.empty()) return e;
  const auto ds = CheckDeltas();
  *analytic = false;
  for (std::size_t k = 0; k < xs.size(); ++k) {
    const Value& x = xs[k];
    for (const Vec15& d : ds) {
      Value y;
      Vec15 back;
      c.retract(x, d, y);
      c.local(x, y, back);
      const double err = (back - d).cwiseAbs().maxCoeff();
      if (!(err <= kRoundTripTol * (1.0 + d.cwiseAbs().maxCoeff())))
        return "local(x, retract(x, d)) differs from d by " + FormatMax(err) + " at check state " +
               std::to_string(k) + " (|d| = " + FormatMax(d.cwiseAbs().maxCoeff()) + ")";
    }
    Mat15 Ja, Jb;
    const bool has_to = c.jacobian_to_reference(x, Ja);
    const bool has_from = c.jacobian_from_reference(x, Jb);
    if (has_to) {
      const Mat15 Jn = RiddersJacobian([&](const Vec15& d, Vec15& out) {
        Value y;
        c.retract(x, d, y);
        ref_local(x, y, out);
      });
      const double err = (Ja - Jn).cwiseAbs().maxCoeff();
      if (!(err <= kJacobianCheckTol * std::max(1.0, Jn.cwiseAbs().maxCoeff())))
        return "analytic jacobian_to_reference differs from numerical differences by " + FormatMax(err) +
               " at check state " + std::to_string(k);
      *analytic = true;
    }
    if (has_from) {
      const Mat15 Jn = RiddersJacobian([&](const Vec15& e, Vec15& out) {
        Value y;
        ref_retract(x, e, y);
        c.local(x, y, out);
      });
      const double err = (Jb - Jn).cwiseAbs().maxCoeff();
      if (!(err <= kJacobianCheckTol * std::max(1.0, Jn.cwiseAbs().maxCoeff())))
        return "analytic jacobian_from_reference differs from numerical differences by " + FormatMax(err) +
               " at check state " + std::to_string(k);
    }
  }
  return {};
}

std::vector<std::string> BlockVector(const BlockLabels& l) { return {l.begin(), l.end()}; }

}  // namespace

int BlockOffset(const BlockLabels& labels, std::string_view label) {
  for (int i = 0; i < 5; ++i)
    if (labels[i] != nullptr && label == labels[i]) return 3 * i;
  throw Error("unknown block label " + Quoted(label));
}

struct Registry::Impl {
  std::vector<PluginInfo> infos;
  IdMap<ErrorState> states;
  IdMap<PreintConvention> preints;
  IdMap<Propagator> propagators;
  IdMap<Preintegrator> preintegrators;
  std::map<std::pair<dev_t, ino_t>, std::string> loaded_files;  // identity -> path it was loaded as

  const PluginInfo* find(PluginKind kind, std::string_view id) const {
    for (const auto& i : infos)
      if (i.kind == kind && i.id == id) return &i;
    return nullptr;
  }

  template <typename T>
  const T* raw(const IdMap<T>& m, PluginKind kind, std::string_view id) const {
    auto it = m.find(id);
    if (it != m.end()) return it->second.get();
    return get(m, kind, id).get();  // throws with the list of known ids
  }

  template <typename T>
  std::shared_ptr<const T> get(const IdMap<T>& m, PluginKind kind, std::string_view id) const {
    auto it = m.find(id);
    if (it != m.end()) return it->second;
    std::vector<std::string> known;
    for (const auto& [k, v] : m) known.push_back(k);
    throw Error("no " + std::string(KindName(kind)) + " plugin with id " + Quoted(id) +
                " is loaded; known: " + KnownIds(known));
  }
};

Registry::Registry() : impl_(std::make_unique<Impl>()) {
  auto ref = std::make_shared<const detail::PreintReferenceConvention>();
  PluginInfo info;
  info.id = ref->id();
  info.kind = PluginKind::PreintConvention;
  info.file = "built-in";
  info.version = "1.0.0";
  info.summary = "reference chart for increments: dR Exp(dtheta), dp, dv, Delta b additive";
  info.blocks = BlockVector(ref->labels());
  info.jacobian_convention = ref->bias_jacobian_chart();
  info.analytic_jacobians = true;
  impl_->infos.push_back(info);
  impl_->preints.emplace(info.id, ref);
}

Registry::~Registry() = default;

namespace {

// A second file declaring a (kind, id) already loaded. load_file reports it like any other
// error; load_directory and load_search_path make it fatal unless an override is allowed.
class DuplicateId : public Error {
 public:
  DuplicateId(PluginKind kind, const std::string& id, const std::string& first, const std::string& second)
      : Error("duplicate " + std::string(KindName(kind)) + " plugin id " + Quoted(id) + ": " + Quoted(first) +
              " (found first) and " + Quoted(second)),
        kind_(kind),
        id_(id),
        first_(first),
        second_(second) {}
  std::string override_message() const {
    return "duplicate " + std::string(KindName(kind_)) + " plugin id " + Quoted(id_) + ": " + Quoted(second_) +
           " is ignored and " + Quoted(first_) + ", earlier on the search path, is used (override allowed)";
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
  std::string msg = duplicates.size() == 1 ? duplicates[0]
                                           : std::to_string(duplicates.size()) + " duplicate plugin ids:";
  if (duplicates.size() > 1)
    for (const auto& d : duplicates) msg += "\n" + d;
  return msg + "\nrefusing to choose between two plugins with one id: remove one, or allow the override "
               "(imuconv: --allow-plugin-override; a pipeline: \"allow_plugin_override\": true) to use the one "
               "earlier on the search path";
}

// Loads every imuconv_plugin_*.so in dir into reg. Failures become issues; duplicate ids are
// issues with an override, else collected in `duplicates` for the caller to throw.
void ScanDirectory(Registry& reg, const std::string& dir, const LoadOptions& options, std::vector<LoadIssue>& issues,
                   std::vector<std::string>& duplicates) {
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
    if (name.size() > 3 && name.rfind("imuconv_plugin_", 0) == 0 && name.compare(name.size() - 3, 3, ".so") == 0)
      files.push_back(it->path().string());
  }
  if (ec) issues.push_back({dir, "listing the plugin directory stopped early: " + ec.message()});
  std::sort(files.begin(), files.end());  // deterministic order
  for (const auto& f : files) {
    try {
      reg.load_file(f);
    } catch (const DuplicateId& d) {
      if (options.allow_override)
        issues.push_back({f, d.override_message(), true});
      else
        duplicates.push_back(d.what());
    } catch (const std::exception& e) {
      issues.push_back({f, e.what()});
    } catch (...) {
      issues.push_back({f, "failed to load with an exception that is not a std::exception"});
    }
  }
}

}  // namespace

void Registry::load_file(const std::string& path) {
  const std::string where = Quoted(path);
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0 && errno == ENOENT) throw Error("plugin file " + where + " does not exist");
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
    throw Error("cannot load " + where + " as a shared library: " + Printable(why ? why : "dlopen failed"));
  }
  auto lib = std::make_shared<boost::dll::shared_library>();
  boost::dll::fs::error_code ec;
  lib->load(abs, boost::dll::load_mode::rtld_now | boost::dll::load_mode::rtld_local, ec);
  if (ec || !lib->is_loaded())
    throw Error("cannot load " + where + " as a shared library: " + (ec ? ec.message() : "unknown error"));
  for (const char* sym : {"imuconv_plugin_abi", "imuconv_plugin_describe", "imuconv_plugin_create",
                          "imuconv_plugin_destroy"}) {
    if (!lib->has(sym)) throw Error(where + " is not an imuconv plugin: it does not export '" + sym + "'");
  }
  // The entry points are fetched without noexcept: one that throws anyway is caught by
  // CallPlugin and named, instead of reaching std::terminate through a noexcept call.
  // 1. ABI handshake before anything else is called.
  const int abi = detail::CallPlugin(path, "imuconv_plugin_abi()", [&] { return lib->get_alias<int()>("imuconv_plugin_abi")(); });
  if (abi != kPluginAbiVersion)
    throw Error(where + " was built for imuconv plugin ABI version " + std::to_string(abi) +
                "; this imuconv speaks version " + std::to_string(kPluginAbiVersion) + ": rebuild the plugin");
  const PluginDescriptor* d = detail::CallPlugin(path, "imuconv_plugin_describe()", [&] {
    return lib->get_alias<const PluginDescriptor*()>("imuconv_plugin_describe")();
  });
  if (d == nullptr) throw Error(where + " returned no plugin descriptor");
  const AbiFingerprint want;
  const AbiFingerprint& got = d->fingerprint;
  if (got.abi_version != want.abi_version || got.eigen_max_static_align != want.eigen_max_static_align ||
      got.sizeof_state != want.sizeof_state || got.sizeof_window != want.sizeof_window ||
      got.gnu_major != want.gnu_major || got.cxx_abi != want.cxx_abi)
    throw Error(where + " has an incompatible binary layout (Eigen alignment " +
                std::to_string(got.eigen_max_static_align) + " vs " + std::to_string(want.eigen_max_static_align) +
                ", ImuState size " + std::to_string(got.sizeof_state) + " vs " + std::to_string(want.sizeof_state) +
                ", g++ " + std::to_string(got.gnu_major) + " vs " + std::to_string(want.gnu_major) +
                "): rebuild it with the same compiler and flags as imuconv");
  const int kind_value = static_cast<int>(d->kind);
  if (kind_value < 1 || kind_value > 4)
    throw Error(where + " declares an unknown plugin kind " + std::to_string(kind_value));
  if (const std::string why = detail::IdProblem(d->id); !why.empty())
    throw Error("plugin " + where + ": its descriptor's id " + why);
  const std::string id = d->id;
  if (d->version == nullptr)
    throw Error("plugin " + where + " (" + Quoted(id) + "): its descriptor's version is a null pointer (expected a string such as \"1.0.0\")");
  if (d->summary == nullptr)
    throw Error("plugin " + where + " (" + Quoted(id) + "): its descriptor's summary is a null pointer (expected a one-line description)");
  if (const PluginInfo* other = impl_->find(d->kind, id)) throw DuplicateId(d->kind, id, other->file, path);

  // 2. Create inside the plugin; destroy inside the plugin; the deleter keeps lib alive.
  auto create = lib->get_alias<void*()>("imuconv_plugin_create");
  auto destroy = lib->get_alias<void(void*)>("imuconv_plugin_destroy");
  void* raw = detail::CallPlugin(path, "imuconv_plugin_create()", [&] { return create(); });
  if (raw == nullptr) throw Error(where + " failed to create its " + Quoted(id) + " object");

  PluginInfo info;
  info.id = id;
  info.kind = d->kind;
  info.file = path;
  info.version = d->version;
  info.summary = d->summary;

  auto wrap = [&](auto* typed) {
    using T = std::remove_pointer_t<decltype(typed)>;
    return std::shared_ptr<const T>(typed, [lib, destroy](const T* p) {
      // A destroy() that throws has no one left to tell (this runs in a destructor); the
      // object may leak, the host carries on.
      try {
        destroy(const_cast<T*>(p));
      } catch (...) {
      }
    });
  };
  auto id_check = [&](const char* got_id) {
    if (got_id == nullptr) throw Error("plugin " + where + ": id() returned a null pointer (expected " + Quoted(id) + ")");
    const std::string_view got_view(got_id, strnlen(got_id, detail::kMaxPluginIdLength + 1));
    if (got_view != id)
      throw Error("plugin " + where + ": object id " + Quoted(got_view) + " differs from the descriptor's id " + Quoted(id));
  };
  // An id naming another plugin (a convention), returned by the object.
  auto ref_id = [&](const char* got, const char* what) -> std::string {
    if (const std::string why = detail::IdProblem(got); !why.empty())
      throw Error("plugin " + where + " (" + Quoted(id) + "): " + what + " " + why);
    return got;
  };

  switch (d->kind) {
    case PluginKind::StateConvention: {
      auto obj = wrap(static_cast<ErrorState*>(raw));
      id_check(obj->id());
      bool analytic = false;
      const std::string err = CheckConvention(*obj, CheckStates(), LeftRetract, LeftLocal, &analytic);
      if (!err.empty()) throw Error("state convention " + Quoted(id) + " in " + where + " is refused: " + err);
      info.blocks = BlockVector(obj->labels());
      info.analytic_jacobians = analytic;
      impl_->states.emplace(id, obj);
      break;
    }
    case PluginKind::PreintConvention: {
      auto obj = wrap(static_cast<PreintConvention*>(raw));
      id_check(obj->id());
      bool analytic = false;
      const std::string err =
          CheckConvention(*obj, CheckIncrements(), PreintReferenceRetract, PreintReferenceLocal, &analytic);
      if (!err.empty()) throw Error("increment convention " + Quoted(id) + " in " + where + " is refused: " + err);
      info.blocks = BlockVector(obj->labels());
      info.analytic_jacobians = analytic;
      info.jacobian_convention = ref_id(obj->bias_jacobian_chart(), "bias_jacobian_chart()");
      impl_->preints.emplace(id, obj);
      break;
    }
    case PluginKind::Propagator: {
      auto obj = wrap(static_cast<Propagator*>(raw));
      id_check(obj->id());
      info.native_convention = ref_id(obj->native_convention(), "native_convention()");
      impl_->propagators.emplace(id, obj);
      break;
    }
    case PluginKind::Preintegrator: {
      auto obj = wrap(static_cast<Preintegrator*>(raw));
      id_check(obj->id());
      info.native_convention = ref_id(obj->cov_convention(), "cov_convention()");
      info.jacobian_convention = ref_id(obj->jacobian_convention(), "jacobian_convention()");
      impl_->preintegrators.emplace(id, obj);
      break;
    }
  }
  impl_->infos.push_back(std::move(info));
  impl_->loaded_files.emplace(identity, path);
}

std::vector<LoadIssue> Registry::load_directory(const std::string& dir, const LoadOptions& options) {
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
      const std::string part = s.substr(start, colon == std::string::npos ? std::string::npos : colon - start);
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
  for (const auto& dir : search_path(extra_dirs)) ScanDirectory(*this, dir, options, issues, duplicates);
  if (!duplicates.empty()) throw Error(WithOverrideHint(duplicates));
  return issues;
}

const std::vector<PluginInfo>& Registry::plugins() const { return impl_->infos; }

const PluginInfo& Registry::info(PluginKind kind, std::string_view id) const {
  if (const PluginInfo* i = impl_->find(kind, id)) return *i;
  throw Error("no " + std::string(KindName(kind)) + " plugin with id " + Quoted(id) +
              " is loaded; known: " + KnownIds(ids(kind)));
}

bool Registry::has(PluginKind kind, std::string_view id) const { return impl_->find(kind, id) != nullptr; }

std::vector<std::string> Registry::ids(PluginKind kind) const {
  std::vector<std::string> out;
  for (const auto& i : impl_->infos)
    if (i.kind == kind) out.push_back(i.id);
  return out;
}

std::shared_ptr<const ErrorState> Registry::state_convention(std::string_view id) const {
  return impl_->get(impl_->states, PluginKind::StateConvention, id);
}
std::shared_ptr<const PreintConvention> Registry::preint_convention(std::string_view id) const {
  return impl_->get(impl_->preints, PluginKind::PreintConvention, id);
}
std::shared_ptr<const Propagator> Registry::propagator(std::string_view id) const {
  return impl_->get(impl_->propagators, PluginKind::Propagator, id);
}
std::shared_ptr<const Preintegrator> Registry::preintegrator(std::string_view id) const {
  return impl_->get(impl_->preintegrators, PluginKind::Preintegrator, id);
}

// ---- conversions (by id; the work is in conversion.cpp) -----------------------------------

Mat15 Registry::to_reference(std::string_view from, const ImuState& x) const {
  return ToReference(*impl_->raw(impl_->states, PluginKind::StateConvention, from), x);
}

Mat15 Registry::from_reference(std::string_view to, const ImuState& x) const {
  return FromReference(*impl_->raw(impl_->states, PluginKind::StateConvention, to), x);
}

Mat15 Registry::conversion(std::string_view from, std::string_view to, const ImuState& x) const {
  return Conversion(*impl_->raw(impl_->states, PluginKind::StateConvention, from),
                    *impl_->raw(impl_->states, PluginKind::StateConvention, to), x);
}

Mat15 Registry::convert_covariance(std::string_view from, std::string_view to, const ImuState& x,
                                   const Mat15& S) const {
  return ConvertCovariance(*impl_->raw(impl_->states, PluginKind::StateConvention, from),
                           *impl_->raw(impl_->states, PluginKind::StateConvention, to), x, S);
}

Mat15 Registry::convert_transition(std::string_view from, std::string_view to, const ImuState& x_s,
                                   const ImuState& x_e, const Mat15& Phi) const {
  return ConvertTransition(*impl_->raw(impl_->states, PluginKind::StateConvention, from),
                           *impl_->raw(impl_->states, PluginKind::StateConvention, to), x_s, x_e, Phi);
}

Mat15 Registry::preint_to_reference(std::string_view from, const PreintIncrement& x) const {
  return ToReference(*impl_->raw(impl_->preints, PluginKind::PreintConvention, from), x);
}

Mat15 Registry::preint_from_reference(std::string_view to, const PreintIncrement& x) const {
  return FromReference(*impl_->raw(impl_->preints, PluginKind::PreintConvention, to), x);
}

Mat15 Registry::preint_conversion(std::string_view from, std::string_view to, const PreintIncrement& x) const {
  return Conversion(*impl_->raw(impl_->preints, PluginKind::PreintConvention, from),
                    *impl_->raw(impl_->preints, PluginKind::PreintConvention, to), x);
}

PropagationResult Registry::propagate(std::string_view propagator_id, std::string_view convention,
                                      const PropagationInput& in) const {
  const Propagator* prop = impl_->raw(impl_->propagators, PluginKind::Propagator, propagator_id);
  const ErrorState* native = impl_->raw(impl_->states, PluginKind::StateConvention, prop->native_convention());
  return PropagateIn(*prop, *native, *impl_->raw(impl_->states, PluginKind::StateConvention, convention), in);
}

}  // namespace imuconv
