// Measurements as values: a measurements file (schemas/measurements.schema.json) written from
// Python through the library's atomic output file, and imuconv check on values — a
// Preintegrated, an Expressed, a dict in the file's form (NumPy arrays allowed), or a list of
// them — over samples given as an (N, 7) array with their noise, not only over files. Values
// are turned into the file's form by the writer the pipeline's preintegrate task uses and read
// back by the reader `imuconv check` uses, so the two paths cannot disagree.
#include <pybind11/stl.h>

#include <optional>
#include <string>
#include <vector>

#include "bindings.h"
#include "imuconv/check/check.h"
#include "imuconv/check/report.h"
#include "imuconv/pipeline/imu_plausibility.h"
#include "imuconv/pipeline/json_writer.h"
#include "imuconv/pipeline/measurement.h"
#include "imuconv/pipeline/output_file.h"

namespace imuconv::python {
namespace {

using nlohmann::json;

/// One Preintegrated or Expressed (taken back to the reference charts; FromConvention is exact
/// up to round-off).
std::optional<Preintegrated> AsPreintegrated(const LoadedRegistry& r, py::handle h) {
  if (py::isinstance<Preintegrated>(h)) return h.cast<Preintegrated>();
  if (py::isinstance<Expressed>(h)) return FromConvention(r, h.cast<const Expressed&>());
  return std::nullopt;
}

/// A single value or a list/tuple of them, as a list.
std::vector<py::handle> Items(py::handle measurements) {
  std::vector<py::handle> out;
  if (py::isinstance<py::list>(measurements) || py::isinstance<py::tuple>(measurements)) {
    for (py::handle h : measurements) out.push_back(h);
    if (out.empty())
      throw py::value_error("measurements: an empty list (give at least one measurement)");
  } else {
    out.push_back(measurements);
  }
  return out;
}

/// t_start: None, one number (one measurement) or one number per measurement.
std::vector<std::optional<double>> Starts(py::handle t_start, std::size_t n,
                                          std::optional<double> fallback) {
  std::vector<std::optional<double>> out(n, fallback);
  if (t_start.is_none()) return out;
  // One number, a list or an array alike, through NumPy (a string or an object is a ValueError).
  std::vector<double> given;
  try {
    given = py::module_::import("numpy")
                .attr("asarray")(t_start, py::arg("dtype") = "float64")
                .attr("ravel")()
                .attr("tolist")()
                .cast<std::vector<double>>();
  } catch (py::error_already_set&) {
    throw py::value_error("t_start: expected a number or a list of numbers");
  }
  if (given.size() != n)
    throw py::value_error("t_start: expected " + std::to_string(n) +
                          " start time(s), one per measurement, got " +
                          std::to_string(given.size()));
  for (std::size_t k = 0; k < n; ++k) {
    if (!std::isfinite(given[k]))
      throw py::value_error("t_start[" + std::to_string(k) + "]: must be finite");
    out[k] = given[k];
  }
  return out;
}

/// The measurements file's text for Preintegrated values: each as a preintegrate task writes
/// it (t_start, t_end = t_start + dt when the start is known; J_bias and cov in
/// preint_reference; "expressed" in each of `conventions`).
std::string DocumentText(const LoadedRegistry& r, const std::vector<Preintegrated>& ms,
                         const std::vector<std::optional<double>>& starts,
                         const std::vector<std::string>& conventions) {
  for (const auto& c : conventions)
    r.info(PluginKind::IncrementConvention, c);  // an unknown id: Error, named
  std::string text;
  pipeline::JsonWriter w(text);
  w.begin_object();
  w.key("measurements");
  w.begin_array();
  for (std::size_t k = 0; k < ms.size(); ++k) {
    pipeline::MeasRecord rec;
    rec.m = ms[k];
    rec.t_s = starts[k];
    if (starts[k]) rec.t_e = *starts[k] + ms[k].dt;
    pipeline::WriteMeasurement(w, rec, k, conventions, r, pipeline::OmitSpec{}, std::nullopt);
  }
  w.end_array();
  w.end_object();
  text += "\n";
  return text;
}

std::vector<Preintegrated> PreintegratedItems(const LoadedRegistry& r,
                                              const std::vector<py::handle>& items) {
  std::vector<Preintegrated> out;
  for (std::size_t k = 0; k < items.size(); ++k) {
    auto m = AsPreintegrated(r, items[k]);
    if (!m)
      throw py::value_error("measurements[" + std::to_string(k) +
                            "]: expected a Preintegrated or an Expressed, got " +
                            std::string(py::str(py::type::of(items[k]).attr("__name__"))));
    out.push_back(std::move(*m));
  }
  return out;
}

/// The JSON pointer (below `pointer`) of the first integer in o that no double holds, or
/// nothing: dicts by key, lists and tuples by index, as json.dumps walks them.
std::optional<std::string> IntegerBeyondDouble(py::handle o, const std::string& pointer) {
  if (PyLong_Check(o.ptr()) && !PyBool_Check(o.ptr())) {
    PyLong_AsDouble(o.ptr());
    if (!PyErr_Occurred()) return std::nullopt;
    PyErr_Clear();
    return pointer;
  }
  if (py::isinstance<py::dict>(o)) {
    for (auto item : py::reinterpret_borrow<py::dict>(o)) {
      const std::string key = py::str(item.first);
      std::string escaped;  // RFC 6901: ~ as ~0, / as ~1
      for (char c : key) escaped += c == '~' ? "~0" : c == '/' ? "~1" : std::string(1, c);
      if (auto at = IntegerBeyondDouble(item.second, pointer + "/" + escaped)) return at;
    }
  } else if (py::isinstance<py::list>(o) || py::isinstance<py::tuple>(o)) {
    std::size_t k = 0;
    for (py::handle item : o)
      if (auto at = IntegerBeyondDouble(item, pointer + "/" + std::to_string(k++))) return at;
  }
  return std::nullopt;
}

/// A dict in the file's form (a whole document with "measurements", or one measurement
/// object) as JSON: NumPy arrays and scalars through tolist(); NaN and infinities refused.
json DictDocument(py::handle d) {
  const py::module_ pyjson = py::module_::import("json");
  const py::cpp_function to_list([](py::handle o) -> py::object {
    if (py::hasattr(o, "tolist")) return o.attr("tolist")();
    throw py::type_error("measurements: a value of type " +
                         std::string(py::str(py::type::of(o).attr("__name__"))) +
                         " is not a number, list, dict or NumPy array");
  });
  py::object text;
  try {
    text = pyjson.attr("dumps")(d, py::arg("default") = to_list, py::arg("allow_nan") = false);
  } catch (py::error_already_set& e) {
    if (e.matches(PyExc_ValueError))
      throw py::value_error("measurements: " + std::string(py::str(e.value())) +
                            " (every number must be finite)");
    throw;
  }
  const bool whole = py::isinstance<py::dict>(d) && d.contains("measurements");
  try {
    json doc = json::parse(text.cast<std::string>());
    if (!doc.contains("measurements")) doc = json{{"measurements", json::array({doc})}};
    return doc;
  } catch (const json::exception& e) {
    // json.dumps writes Python's unbounded integers in full; one past the largest double
    // (10**400) cannot be read as a number. Named by its pointer in the file's form, as the
    // measurement reader names every other bad value.
    const auto at = IntegerBeyondDouble(d, whole ? "" : "/measurements/0");
    if (at)
      throw Error("measurements (dict): " + *at +
                  ": expected a number within double precision, found an integer beyond "
                  "1.8e308");
    throw Error(std::string("measurements (dict): not readable as JSON numbers: ") + e.what());
  }
}

}  // namespace

void BindMeasurements(py::module_& m) {
  m.def(
      "write_measurements",
      [](py::handle path, const LoadedRegistry& r, py::handle measurements, py::handle t_start,
         const std::vector<std::string>& conventions) {
        const std::string file = PathArgument(path, "path");
        const auto items = Items(measurements);
        const std::vector<Preintegrated> ms = PreintegratedItems(r, items);
        const auto starts = Starts(t_start, ms.size(), std::nullopt);
        const std::string text = DocumentText(r, ms, starts, conventions);
        try {
          py::gil_scoped_release release;
          // The library's output file: a regular file is replaced atomically (never half
          // written); a directory or an unwritable path is an Error naming it. A FIFO with no
          // reader blocks in open until one comes, or until Ctrl-C.
          pipeline::OutputFile out(file);
          out.write(text);
          out.commit();
        } catch (const std::exception&) {
          RaiseIfInterrupted();
          throw;
        }
      },
      py::arg("path"), py::arg("reg"), py::arg("measurements"), py::kw_only(),
      py::arg("t_start") = py::none(), py::arg("conventions") = std::vector<std::string>{},
      "Writes a measurements file (schemas/measurements.schema.json) from a Preintegrated, an "
      "Expressed or a list "
      "of them, as a preintegrate task writes its measurements: J_bias and cov in "
      "preint_reference, and also "
      "expressed in each of `conventions`. t_start: each measurement's start time (one number, or "
      "one per "
      "measurement; t_end = t_start + dt); without it the file has no times. The file is replaced "
      "atomically "
      "(never half written); `imuconv check`, imuconv.check and the pipeline's tasks read it.");

  m.def(
      "check",
      [](const LoadedRegistry& r, py::handle measurements, py::handle case_file, py::handle samples,
         py::handle noise, py::handle t_start) {
        if (case_file.is_none() == samples.is_none())
          throw py::value_error(
              "give the IMU samples with one of case= (a reference case file) and samples= (an "
              "(N, 7) array, with noise=)");
        if (!case_file.is_none() && !noise.is_none())
          throw py::value_error("noise: the case file holds its noise; noise= goes with samples=");
        check::CaseInput input;
        std::string source;
        if (!samples.is_none()) {
          input.samples = ReadSamples(samples, /*allow_gaps=*/false);
          input.noise = ReadNoise(noise);
          RequireUsableNoise(input.noise, input.samples);  // as a case file's noise is checked
          input.source = "the samples given";
          source = "samples";
        } else {
          source = PathArgument(case_file, "case");
          try {
            py::gil_scoped_release release;
            input = check::ReadCaseFile(source);  // at least 2 samples, or an Error naming it
          } catch (const std::exception&) {
            RaiseIfInterrupted();  // a FIFO's open blocks until Ctrl-C
            throw;
          }
        }
        // The measurements: a file, or values turned into the file's form and read alike.
        std::optional<json> doc;
        std::string meas_name;
        if (IsPathArgument(measurements)) {
          meas_name = PathArgument(measurements, "measurements");
          if (!t_start.is_none())
            throw py::value_error("t_start: a measurements file holds its own times");
        } else if (py::isinstance<py::dict>(measurements) ||
                   ((py::isinstance<py::list>(measurements) ||
                     py::isinstance<py::tuple>(measurements)) &&
                    py::len(measurements) > 0 &&
                    py::isinstance<py::dict>(measurements[py::int_(0)]))) {
          if (!t_start.is_none())
            throw py::value_error("t_start: a dict holds its own t_start and t_end");
          meas_name = "measurements (dict)";
          if (py::isinstance<py::dict>(measurements)) {
            doc = DictDocument(measurements);
          } else {
            py::dict whole;
            whole["measurements"] = measurements;
            doc = DictDocument(whole);
          }
        } else {
          const std::vector<Preintegrated> ms = PreintegratedItems(r, Items(measurements));
          // Default: the interval starts at the first sample (as preintegrate's default window).
          const auto starts = Starts(t_start, ms.size(), input.samples.front().t);
          meas_name = "measurements (values)";
          doc = json::parse(DocumentText(r, ms, starts, {}));
        }
        std::string report;
        std::vector<std::string> warnings;
        try {
          py::gil_scoped_release release;
          warnings = pipeline::ImuPlausibilityWarnings(input.samples, source);
          const auto ms = doc ? pipeline::ReadDeclaredMeasurementDocument(*doc, meas_name, r)
                              : pipeline::ReadDeclaredMeasurementFile(meas_name, r);
          json out = check::ReportJson(check::RunCheck(r, input, ms, meas_name));
          if (!warnings.empty()) out["warnings"] = warnings;
          report = out.dump();
        } catch (const std::exception&) {
          RaiseIfInterrupted();  // reading a measurements file that is a FIFO blocks until Ctrl-C
          throw;
        }
        for (const auto& w : warnings)
          if (PyErr_WarnEx(PyExc_UserWarning, ("imuconv: " + w).c_str(), 1) != 0)
            throw py::error_already_set();
        return py::module_::import("json").attr("loads")(report);
      },
      py::arg("reg"), py::arg("measurements"), py::kw_only(), py::arg("case") = py::none(),
      py::arg("samples") = py::none(), py::arg("noise") = py::none(),
      py::arg("t_start") = py::none(),
      "imuconv check as a call. measurements: a measurements file (any chart may be \"unknown\"), "
      "a dict in that "
      "file's form (one measurement or the whole document; NumPy arrays allowed; charts may be "
      "\"unknown\"), or a "
      "Preintegrated / Expressed (or a list of them), whose start time is t_start (default: the "
      "first sample's). "
      "The samples: case= (a reference case file) or samples= (N, 7: t, wx, wy, wz, ax, ay, az) "
      "with noise= (the "
      "four densities). Returns the report `imuconv check --json` prints "
      "(schemas/check_output.schema.json), with "
      "'warnings' when the samples look mistaken (units, column order; also issued as "
      "UserWarning). Unusable input "
      "raises imuconv.Error naming the file (or value) and pointer, or ValueError naming the "
      "argument.");
}

}  // namespace imuconv::python
