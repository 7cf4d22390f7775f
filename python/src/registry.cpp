// Registry: the built-in plugins, IMUCONV_PLUGIN_PATH and the caller's directories, and the
// conversions between conventions (registry/include/imuconv/registry.h). A Registry is
// immutable once built, so its methods release the GIL while they compute.
#include "imuconv/registry.h"

#include <pybind11/stl.h>

#include <string>
#include <vector>

#include "arrays.h"
#include "bindings.h"
#include "finite_results.h"
#include "imuconv/numeric.h"
#include "imuconv/printable.h"

namespace imuconv::python {
namespace {

// A chart's retract and local as the module gives them, for a state and an increment
// convention alike: d read as a (15,) array named "d", the perturbation returned as one. A
// finite d can still take a chart past double precision (1e308 in every entry, a rotation of
// 1e200 rad in an SE_2(3) chart): such a result is a ValueError naming `call`, never returned.
template <class Value>
Value ChartRetract(const Chart<Value>& chart, const Value& x, py::handle d, const char* call) {
  const Vec15 dx = ToFixed<15, 1>(d, "d");
  Value y;
  chart.retract(x, dx, y);
  return FiniteValue(y, call);
}
template <class Value>
py::array ChartLocal(const Chart<Value>& chart, const Value& x, const Value& y, const char* call) {
  Vec15 d;
  chart.local(x, y, d);
  return ToArray(FiniteMatrix(d, call, "d"));
}

py::dict InfoDict(const PluginInfo& p) {
  py::dict d;
  d["id"] = p.id;
  d["kind"] = KindName(p.kind);
  d["file"] = p.file;
  d["version"] = p.version;
  d["summary"] = p.summary;
  d["blocks"] = p.blocks;
  d["native_convention"] = p.native_convention;
  d["jacobian_convention"] = p.jacobian_convention;
  d["analytic_jacobians"] = p.analytic_jacobians;
  return d;
}

PluginKind KindFromName(const std::string& name) {
  for (PluginKind k : kPluginKinds)
    if (name == KindName(k)) return k;
  throw py::value_error("unknown plugin kind '" + name +
                        "' (expected state_convention, preint_convention, propagator, "
                        "preintegrator or residual)");
}

}  // namespace

Mat15 CheckedCovariance(py::handle obj, const char* name) {
  const Mat15 S = ToFixed<15, 15>(obj, name);
  const std::string problem = CovarianceProblem(S);
  if (!problem.empty())
    throw py::value_error(std::string(name) + ": not a valid covariance: " + problem);
  return S;
}

void BindRegistry(py::module_& m) {
  py::class_<LoadedRegistry> reg(
      m, "Registry",
      "Loaded plugins and the conversions between their conventions. Registry() loads the "
      "directories given, then those of IMUCONV_PLUGIN_PATH, then the built-in plugins; a "
      "file that fails to load is reported in load_issues (and as a warning), the rest load.");
  reg.def(
      py::init([](const std::vector<std::string>& plugin_dirs, bool allow_override) {
        auto r = std::make_unique<LoadedRegistry>();
        LoadOptions o;
        o.allow_override = allow_override;
        r->load_issues = r->load_search_path(plugin_dirs, o);
        for (const auto& i : r->load_issues)
          // Named as the CLI names it ("DIR: plugin directory does not exist"): the message
          // alone does not say which of the directories or files it is about.
          if (PyErr_WarnEx(PyExc_RuntimeWarning,
                           ("imuconv: " + Printable(i.file) + ": " + Printable(i.message)).c_str(),
                           1) != 0)
            throw py::error_already_set();  // warnings turned into errors
        return r;
      }),
      py::arg("plugin_dirs") = std::vector<std::string>{}, py::kw_only(),
      py::arg("allow_override") = false);
  reg.def("__repr__", [](const LoadedRegistry& r) {
    // What is loaded, kind by kind, and whether anything failed: the first question about a
    // registry in an interactive session.
    std::string t = "Registry(";
    for (const auto kind : kPluginKinds) {
      t += std::string(KindName(kind)) + "=" + Labels(r.ids(kind)) +
           ", ";  // as reg.ids(kind) names them
    }
    return t + "load_issues=" + std::to_string(r.load_issues.size()) + ")";
  });
  reg.def_property_readonly(
      "load_issues",
      [](const LoadedRegistry& r) {
        py::list list;
        for (const auto& i : r.load_issues) {
          py::dict d;
          d["file"] = i.file;
          d["message"] = i.message;
          d["overridden"] = i.overridden;
          list.append(d);
        }
        return list;
      },
      "The plugin files that were not loaded, and why: dicts with file, message, overridden.");
  reg.def(
      "plugins",
      [](const LoadedRegistry& r) {
        py::list out;
        for (const auto& p : r.plugins()) out.append(InfoDict(p));
        return out;
      },
      "Every loaded plugin: dicts with id, kind, file, version, summary, blocks, "
      "native_convention, "
      "jacobian_convention, analytic_jacobians.");
  reg.def(
      "ids",
      [](const LoadedRegistry& r, const std::string& kind) { return r.ids(KindFromName(kind)); },
      py::arg("kind"),
      "The ids of one kind: state_convention, preint_convention, propagator or preintegrator.");
  reg.def(
      "info",
      [](const LoadedRegistry& r, const std::string& kind, const std::string& id) {
        return InfoDict(r.info(KindFromName(kind), id));
      },
      py::arg("kind"), py::arg("id"));
  reg.def_static(
      "search_path",
      [](const std::vector<std::string>& dirs) { return Registry::search_path(dirs); },
      py::arg("plugin_dirs") = std::vector<std::string>{});

  // ---- state conventions
  reg.def(
      "conversion",
      [](const LoadedRegistry& r, const std::string& from, const std::string& to,
         const ImuState& x) {
        Mat15 J;
        {
          py::gil_scoped_release release;
          J = r.conversion(from, to, x);
        }
        return ToArray(FiniteMatrix(J, "conversion", "result"));
      },
      py::arg("from_convention"), py::arg("to_convention"), py::arg("x"),
      "d dx_to / d dx_from at x (15, 15): the Jacobian that carries a perturbation in one state "
      "convention "
      "into another.");
  reg.def(
      "convert_covariance",
      [](const LoadedRegistry& r, const std::string& from, const std::string& to, const ImuState& x,
         py::handle S) {
        const Mat15 cov = CheckedCovariance(S, "S");
        Mat15 out;
        {
          py::gil_scoped_release release;
          out = r.convert_covariance(from, to, x, cov);
        }
        return ToArray(FiniteMatrix(out, "convert_covariance", "result"));
      },
      py::arg("from_convention"), py::arg("to_convention"), py::arg("x"), py::arg("S"),
      "A covariance at x in one state convention, in another: J S J^T.");
  reg.def(
      "convert_transition",
      [](const LoadedRegistry& r, const std::string& from, const std::string& to,
         const ImuState& x_s, const ImuState& x_e, py::handle Phi) {
        const Mat15 P = ToFixed<15, 15>(Phi, "Phi");
        Mat15 out;
        {
          py::gil_scoped_release release;
          out = r.convert_transition(from, to, x_s, x_e, P);
        }
        return ToArray(FiniteMatrix(out, "convert_transition", "result"));
      },
      py::arg("from_convention"), py::arg("to_convention"), py::arg("x_s"), py::arg("x_e"),
      py::arg("Phi"),
      "A transition matrix from x_s to x_e, in another state convention: J_e Phi J_s^-1.");
  reg.def(
      "retract",
      [](const LoadedRegistry& r, const std::string& convention, const ImuState& x, py::handle d) {
        return ChartRetract(*r.state_convention(convention), x, d, "retract");
      },
      py::arg("convention"), py::arg("x"), py::arg("d"),
      "The state convention's chart: x perturbed by d (15,).");
  reg.def(
      "local",
      [](const LoadedRegistry& r, const std::string& convention, const ImuState& x,
         const ImuState& y) { return ChartLocal(*r.state_convention(convention), x, y, "local"); },
      py::arg("convention"), py::arg("x"), py::arg("y"),
      "The state convention's chart: d with retract(x, d) = y.");

  // ---- increment conventions
  reg.def(
      "increment_conversion",
      [](const LoadedRegistry& r, const std::string& from, const std::string& to,
         const PreintIncrement& d) {
        return ToArray(FiniteMatrix(r.conversion(from, to, d), "increment_conversion", "result"));
      },
      py::arg("from_convention"), py::arg("to_convention"), py::arg("delta"),
      "d dx_to / d dx_from at the increment delta (15, 15).");
  reg.def(
      "increment_retract",
      [](const LoadedRegistry& r, const std::string& convention, const PreintIncrement& x,
         py::handle d) {
        return ChartRetract(*r.increment_convention(convention), x, d, "increment_retract");
      },
      py::arg("convention"), py::arg("delta"), py::arg("d"));
  reg.def(
      "increment_local",
      [](const LoadedRegistry& r, const std::string& convention, const PreintIncrement& x,
         const PreintIncrement& y) {
        return ChartLocal(*r.increment_convention(convention), x, y, "increment_local");
      },
      py::arg("convention"), py::arg("delta"), py::arg("other"));
  reg.def(
      "blocks",
      [](const LoadedRegistry& r, const std::string& kind, const std::string& id) {
        return r.info(KindFromName(kind), id).blocks;
      },
      py::arg("kind"), py::arg("id"),
      "A convention's block order, e.g. ['theta', 'p', 'v', 'bg', 'ba'].");
}

}  // namespace imuconv::python
