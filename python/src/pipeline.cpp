// Pipelines from Python: imuconv.run(path) runs a JSON pipeline as `imuconv run` does and
// returns its result as NumPy arrays, the same arrays and keys `imuconv run -o OUT.npz` writes
// (apps/pipeline's result_arrays.h, the rule in docs/interop.md), bit for bit the JSON
// output's numbers: the arrays are collected from the values the tasks write (RunToArrays), as
// `imuconv run -o OUT.npz` collects them; no text is formatted and read back.
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "bindings.h"
#include "imuconv/pipeline/pipeline.h"
#include "imuconv/pipeline/result_arrays.h"

namespace imuconv::python {
namespace {

py::array ToNumpy(const pipeline::NdArray& a) {
  std::vector<py::ssize_t> shape(a.shape.begin(), a.shape.end());
  if (a.type == pipeline::NdArray::Type::kInt64) {
    py::array_t<std::int64_t> out(shape);
    std::copy(a.integers.begin(), a.integers.end(), out.mutable_data());
    return std::move(out);
  }
  py::array_t<double> out(shape);
  std::copy(a.data.begin(), a.data.end(), out.mutable_data());
  return std::move(out);
}

}  // namespace

void BindPipeline(py::module_& m) {
  m.def(
      "run",
      [](py::handle pipeline_file, const std::vector<std::string>& plugin_dirs, unsigned threads) {
        const std::string path = PathArgument(pipeline_file, "pipeline");
        pipeline::ResultArrays result;
        std::string log_text;
        try {
          py::gil_scoped_release release;
          const pipeline::Pipeline p = pipeline::Pipeline::Load(path);
          std::ostringstream log;
          pipeline::RunOptions o;
          o.plugin_dirs = plugin_dirs;
          o.threads = threads;
          o.log = &log;
          result = pipeline::RunToArrays(p, o);
          log_text = log.str();
        } catch (const std::exception&) {
          RaiseIfInterrupted();  // a file of the pipeline that is a FIFO blocks until Ctrl-C
          throw;
        }
        if (!log_text.empty() &&
            PyErr_WarnEx(PyExc_RuntimeWarning, ("imuconv: " + log_text).c_str(), 1) != 0)
          throw py::error_already_set();
        py::dict out;
        for (const auto& [key, array] : result.arrays) out[py::str(key)] = ToNumpy(array);
        out[pipeline::kSidecarKey] = py::module_::import("json").attr("loads")(result.sidecar);
        return out;
      },
      py::arg("pipeline"), py::kw_only(), py::arg("plugin_dirs") = std::vector<std::string>{},
      py::arg("threads") = 0u,
      "Runs a JSON pipeline file and returns its result as a dict of NumPy arrays, keyed as "
      "`imuconv run -o "
      "OUT.npz` keys them (e.g. 'tasks/kf_rk4/measurements/J_bias/matrix', shape (n, 9, 6)), with "
      "the sidecar "
      "(conventions, block orders, scalars) as a dict under 'meta'. The numbers are the JSON "
      "output's, bit for bit; "
      "threads: 0 = every core (the result does not depend on it).");
  // imuconv.check: measurements.cpp (files and values).
}

}  // namespace imuconv::python
