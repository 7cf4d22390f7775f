// Registry: loads imuconv plugins with Boost.DLL and composes conventions.
//
// Conversion Jacobians are derived for any pair of registered conventions of one kind,
// with no pair-specific code: every convention is related to its kind's reference chart
// (`left` for states, `preint_reference` for increments, see reference_charts.h), and
//   conversion(A, B, x) = J_{B <- ref}(x) * J_{ref <- A}(x),
// which is the exact chain rule of d local_B(x, retract_A(x, d)) / d d at d = 0. Each factor
// is the plugin's analytic Jacobian (checked against Ridders' differences when the plugin is
// loaded; a wrong one is refused) or, where the plugin gives none, Ridders' differences of
// its own retract/local against the reference chart.
#pragma once

#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "imuconv/chart.h"
#include "imuconv/export.h"
#include "imuconv/plugin_kind.h"
#include "imuconv/preintegrator.h"
#include "imuconv/propagator.h"
#include "imuconv/residual_factor.h"

namespace imuconv {

/// Every error the host-side API reports; the message names the file, id or value at fault.
class IMUCONV_API Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct PluginInfo {
  std::string id;
  PluginKind kind = PluginKind::StateConvention;
  std::string file;  ///< shared object it came from ("built-in" for the reference charts)
  std::string version;
  std::string summary;
  std::vector<std::string> blocks;  ///< block order, for conventions
  std::string native_convention;    ///< propagators: native state convention; preintegrators:
                                    ///< covariance convention; residuals: the increment
                                    ///< convention the measurement is expressed in
  std::string jacobian_convention;  ///< preintegrators and increment conventions: the chart of the
                                    ///< bias Jacobian
  bool analytic_jacobians = false;  ///< conventions: analytic Jacobians given (and verified)
  std::string layout;               ///< residuals: what their numbers are (ResidualFactor::layout)
  int degrees_of_freedom = 0;       ///< residuals: of their squared Mahalanobis distance
};

/// A plugin file that was not loaded, and why. Every bad file on the search path becomes one
/// of these while the others load; the message quotes paths and ids through Printable, `file`
/// is the raw path (print it through Printable too).
struct LoadIssue {
  std::string file;
  std::string message;
  /// True for a duplicate id skipped because LoadOptions::allow_override was set (a warning:
  /// the plugin earlier on the search path is used).
  bool overridden = false;
};

struct LoadOptions {
  /// Two files that declare the same kind and id make load_directory and load_search_path
  /// throw Error naming both, unless this is set; then the one earlier on the search path
  /// wins and the later one is a LoadIssue with overridden = true.
  bool allow_override = false;
};

class IMUCONV_API Registry {
 public:
  Registry();
  ~Registry();
  Registry(const Registry&) = delete;
  Registry& operator=(const Registry&) = delete;

  // ---- loading -------------------------------------------------------------------
  // Loading runs the plugin's code in this process (its static initialisers at dlopen, then
  // its entry points): only load directories you trust. What can be contained is: a C++
  // exception thrown through an entry point, a null or malformed string, a file that is not
  // a shared object all become errors naming the file. A crash or a hang cannot be; use
  // `imuconv plugins --check DIR`, which exercises each file in a child process.

  /// Loads one plugin file. Throws Error (naming the file and the cause) for a missing
  /// file, a file that is not an imuconv plugin, an ABI mismatch, a duplicate id, an
  /// invalid id (not letters, digits, '_', '-', '.'), a null string, an exception thrown by
  /// an entry point or a convention whose charts or analytic Jacobians fail their checks. On
  /// failure the registry is unchanged and stays usable.
  void load_file(const std::string& path);
  /// Loads every imuconv_plugin_*.so in dir (sorted by name); returns what failed (the rest is
  /// loaded), an unreadable directory included. Throws Error for duplicate ids unless
  /// options.allow_override (see LoadOptions).
  [[nodiscard]] std::vector<LoadIssue> load_directory(const std::string& dir,
                                                      const LoadOptions& options = {});
  /// Loads the search path: extra_dirs (e.g. from a pipeline config), then the directories
  /// of IMUCONV_PLUGIN_PATH (colon-separated), then the install or build plugin directory.
  /// Returns what failed to load; throws Error, after the whole path was read and naming both
  /// files of every duplicate id, unless options.allow_override. Do not use the registry
  /// after that throw.
  [[nodiscard]] std::vector<LoadIssue> load_search_path(
      const std::vector<std::string>& extra_dirs = {}, const LoadOptions& options = {});
  static std::vector<std::string> search_path(const std::vector<std::string>& extra_dirs = {});
  /// Adopts the plugins compiled into this process (plugin_abi.h, IMUCONV_PLUGIN_STATIC; the
  /// build option IMUCONV_STATIC_PLUGINS compiles the built-in ones into this library) with
  /// the checks a file's plugin gets; their PluginInfo::file is kCompiledIn. load_search_path
  /// adopts them in place of the built-in plugin directory. Throws Error as load_file does;
  /// plugins adopted before are not adopted again.
  void load_compiled_in();
  /// Whether this process has compiled-in plugins.
  static bool has_compiled_in();
  /// PluginInfo::file of a compiled-in plugin: "compiled-in".
  static const char* const kCompiledIn;
  /// The built-in plugin directory (next to the installed library, else the build tree).
  static std::string default_plugin_dir();

  const std::vector<PluginInfo>& plugins() const;
  const PluginInfo& info(PluginKind kind, std::string_view id) const;
  bool has(PluginKind kind, std::string_view id) const;
  std::vector<std::string> ids(PluginKind kind) const;

  // ---- access (throw Error for an unknown id, listing the known ones) --------------
  std::shared_ptr<const StateConvention> state_convention(std::string_view id) const;
  std::shared_ptr<const IncrementConvention> increment_convention(std::string_view id) const;
  std::shared_ptr<const Propagator> propagator(std::string_view id) const;
  std::shared_ptr<const Preintegrator> preintegrator(std::string_view id) const;
  std::shared_ptr<const ResidualFactor> residual_factor(std::string_view id) const;

  // ---- conversions between two conventions of one kind -------------------------------
  // Written once over the value type: Value is ImuState for state conventions and
  // PreintIncrement for increment conventions (the ids are looked up among that kind; an id
  // of the other kind is unknown). Each throws Error for an unknown id, listing the known ones.

  /// J = d local_to(x, retract_from(x, d)) / d d at d = 0.
  template <class Value>
  [[nodiscard]] Mat15 conversion(std::string_view from, std::string_view to, const Value& x) const;
  /// J_{ref <- from}(x) and J_{to <- ref}(x), ref being the kind's reference chart (`left` or
  /// `preint_reference`).
  template <class Value>
  [[nodiscard]] Mat15 to_reference(std::string_view from, const Value& x) const;
  template <class Value>
  [[nodiscard]] Mat15 from_reference(std::string_view to, const Value& x) const;
  /// A covariance in `from` at x expressed in `to`: J S J^T (symmetrized).
  template <class Value>
  [[nodiscard]] Mat15 convert_covariance(std::string_view from, std::string_view to, const Value& x,
                                         const Mat15& S) const;
  /// A transition matrix from x_s to x_e in `from` expressed in `to`: J_e Phi J_s^{-1},
  /// with J_s^{-1} = conversion(to, from, x_s).
  template <class Value>
  [[nodiscard]] Mat15 convert_transition(std::string_view from, std::string_view to,
                                         const Value& x_s, const Value& x_e,
                                         const Mat15& Phi) const;

  // ---- propagation in any state convention -----------------------------------------
  /// Runs the propagator; in.cov_s and the result's Phi and cov are in `convention`.
  [[nodiscard]] PropagationResult propagate(std::string_view propagator,
                                            std::string_view convention,
                                            const PropagationInput& in) const;

 private:
  struct Impl;
  struct EntryPoints;
  /// The checks and the adoption of one plugin, from its entry points (`path` names it).
  void adopt(const std::string& path, const EntryPoints& entry);
  /// adopt() for entry k of detail::CompiledInPlugins().
  void adopt_compiled_in(std::size_t k);
  std::unique_ptr<Impl> impl_;
};

// The conversions are compiled for the two value types in the registry library.
#define IMUCONV_REGISTRY_CONVERSIONS(EXTERN, V)                                                    \
  EXTERN template IMUCONV_API Mat15 Registry::conversion<V>(std::string_view, std::string_view,    \
                                                            const V&) const;                       \
  EXTERN template IMUCONV_API Mat15 Registry::to_reference<V>(std::string_view, const V&) const;   \
  EXTERN template IMUCONV_API Mat15 Registry::from_reference<V>(std::string_view, const V&) const; \
  EXTERN template IMUCONV_API Mat15 Registry::convert_covariance<V>(                               \
      std::string_view, std::string_view, const V&, const Mat15&) const;                           \
  EXTERN template IMUCONV_API Mat15 Registry::convert_transition<V>(                               \
      std::string_view, std::string_view, const V&, const V&, const Mat15&) const;
IMUCONV_REGISTRY_CONVERSIONS(extern, ImuState)
IMUCONV_REGISTRY_CONVERSIONS(extern, PreintIncrement)

/// Offset of each label's block in a convention's order, e.g. for {"theta","p","v","ba","bg"}
/// BlockOffset(labels, "bg") = 12. Throws Error for an unknown label.
IMUCONV_API int BlockOffset(const BlockLabels& labels, std::string_view label);

}  // namespace imuconv
