// The Python module imuconv._imuconv (imported as imuconv, python/imuconv/__init__.py).
//
// The module links the installed (or built) imuconv libraries, so Registry() finds the
// built-in plugins where the registry library finds them: next to the installed library, or
// in the build tree (Registry::default_plugin_dir).
#include <pybind11/pybind11.h>

#include "bindings.h"
#include "imuconv/pipeline/standard_descriptors.h"
#include "imuconv/registry.h"

PYBIND11_MODULE(_imuconv, m) {
  namespace py = pybind11;
  m.doc() =
      "imuconv: IMU propagation and preintegration as one computation, with perturbation "
      "conventions as "
      "plugins and the conversion Jacobians between any two of them.";
  // Every error of the library (its message names the file, id or value at fault) is
  // imuconv.Error, a RuntimeError; bad arguments are ValueError.
  py::register_exception<imuconv::Error>(m, "Error", PyExc_RuntimeError);
  // A host process started with a standard descriptor closed: /dev/null in its place, so that
  // no file the module opens takes descriptor 0-2 (standard_descriptors.h).
  imuconv::pipeline::OpenClosedStandardDescriptors();
  imuconv::python::BindValues(m);
  imuconv::python::BindRegistry(m);
  imuconv::python::BindBridge(m);
  imuconv::python::BindPipeline(m);
  imuconv::python::BindMeasurements(m);
#ifdef IMUCONV_HAVE_OPTIMIZE
  imuconv::python::BindOptimize(m);
#endif
#ifdef IMUCONV_VERSION
  m.attr("__version__") = IMUCONV_VERSION;
#endif
}
