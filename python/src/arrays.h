// NumPy arrays in and out of the module's fixed-size Eigen types.
//
// Every input array is checked here, by name, before any computation: a wrong shape or a
// non-finite entry is a ValueError that says which argument and what was expected, never
// pybind11's generic "incompatible function arguments" and never a silent reshape. Outputs
// are new float64 arrays (copies): nothing returned aliases the library's memory.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <Eigen/Core>
#include <charconv>
#include <cmath>
#include <string>

#include "imuconv/types.h"

namespace imuconv::python {

namespace py = pybind11;

/// A float64, C-contiguous view of any array-like (lists are converted; other dtypes cast).
using Float64Array = py::array_t<double, py::array::c_style | py::array::forcecast>;

/// The shortest text that reads back as x (what the JSON outputs print).
inline std::string Num(double x) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, x);
  return std::string(buf, r.ptr);
}

inline std::string ShapeText(const py::array& a) {
  std::string s = "(";
  for (py::ssize_t i = 0; i < a.ndim(); ++i) s += (i ? ", " : "") + std::to_string(a.shape(i));
  return s + (a.ndim() == 1 ? ",)" : ")");
}

inline Float64Array AsFloat64(py::handle obj, const char* name) {
  if (obj.is_none())
    throw py::value_error(std::string(name) + ": expected an array of numbers, got None");
  Float64Array a = Float64Array::ensure(obj);  // empty (error cleared) when obj is not numeric
  if (!a) throw py::value_error(std::string(name) + ": expected an array of numbers");
  return a;
}

inline void RequireFinite(const double* data, py::ssize_t n, const char* name) {
  for (py::ssize_t i = 0; i < n; ++i)
    if (!std::isfinite(data[i]))
      throw py::value_error(std::string(name) + ": entry " + std::to_string(i) +
                            " (flat index) is not finite");
}

/// An R x C matrix (shape (R, C)); a vector (C == 1) is given as shape (R,).
template <int R, int C>
Eigen::Matrix<double, R, C> ToFixed(py::handle obj, const char* name) {
  const Float64Array a = AsFloat64(obj, name);
  const bool ok = C == 1 ? (a.ndim() == 1 && a.shape(0) == R)
                         : (a.ndim() == 2 && a.shape(0) == R && a.shape(1) == C);
  if (!ok)
    throw py::value_error(std::string(name) + ": expected shape " +
                          (C == 1 ? "(" + std::to_string(R) + ",)"
                                  : "(" + std::to_string(R) + ", " + std::to_string(C) + ")") +
                          ", got " + ShapeText(a));
  RequireFinite(a.data(), a.size(), name);
  Eigen::Matrix<double, R, C> m;
  for (int i = 0; i < R; ++i)
    for (int j = 0; j < C; ++j) m(i, j) = a.data()[i * C + j];
  return m;
}

/// A new float64 array: shape (R,) for a vector (one column at compile time), else (R, C).
template <typename Derived>
py::array ToArray(const Eigen::MatrixBase<Derived>& m) {
  if constexpr (Derived::ColsAtCompileTime == 1) {
    py::array_t<double> out(static_cast<py::ssize_t>(m.size()));
    for (Eigen::Index i = 0; i < m.size(); ++i) out.mutable_data()[i] = m(i);
    return std::move(out);
  } else {
    py::array_t<double> out(
        {static_cast<py::ssize_t>(m.rows()), static_cast<py::ssize_t>(m.cols())});
    for (Eigen::Index i = 0; i < m.rows(); ++i)
      for (Eigen::Index j = 0; j < m.cols(); ++j) out.mutable_data()[i * m.cols() + j] = m(i, j);
    return std::move(out);
  }
}

}  // namespace imuconv::python
