// Values: State (the 15-dof IMU state) and Increment (a preintegrated increment), with the
// same checks as the pipeline's state form: a quaternion must be unit within 1e-6 and a
// rotation matrix orthonormal within 1e-6 (nothing is silently normalised beyond round-off).
#include <pybind11/stl.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "arrays.h"
#include "bindings.h"
#include "imuconv/pipeline/imu_plausibility.h"
#include "imuconv/pipeline/sample_checks.h"
#include "imuconv/so3.h"

namespace imuconv::python {
namespace {

/// The pipeline's rule (apps/pipeline/src/forms/state.cpp): unit norm within 1e-6.
constexpr double kUnitTol = 1e-6;

Mat3 RotationFromQuaternion(const Eigen::Vector4d& q_wxyz, const char* name) {
  const double n = q_wxyz.norm();
  if (std::abs(n - 1.0) > kUnitTol)
    throw py::value_error(std::string(name) + ": not a unit quaternion (norm " + Num(n) +
                          ", allowed 1 +- 1e-6)");
  return so3::FromQuaternionWxyz(q_wxyz[0], q_wxyz[1], q_wxyz[2], q_wxyz[3]);
}

Mat3 CheckedRotation(py::handle obj, const char* name) {
  const Mat3 R = ToFixed<3, 3>(obj, name);
  const double err = (R.transpose() * R - Mat3::Identity()).cwiseAbs().maxCoeff();
  if (err > kUnitTol || R.determinant() < 0.0)
    throw py::value_error(std::string(name) + ": not a rotation matrix (|R^T R - I| = " + Num(err) +
                          ", det " + Num(R.determinant()) + "; allowed 1e-6 and det > 0)");
  return R;
}

/// Exactly one of the rotation arguments that are not None.
Mat3 OneRotation(py::handle q_wxyz, py::handle R, py::handle q_GtoI_xyzw, const char* what) {
  const int given = !q_wxyz.is_none() + !R.is_none() + !q_GtoI_xyzw.is_none();
  if (given != 1)
    throw py::value_error(std::string(what) + ": give exactly one of q_wxyz, R and q_GtoI_xyzw (" +
                          std::to_string(given) + " given)");
  if (!R.is_none()) return CheckedRotation(R, "R");
  if (!q_wxyz.is_none()) return RotationFromQuaternion(ToFixed<4, 1>(q_wxyz, "q_wxyz"), "q_wxyz");
  // OpenVINS's JPL q_GtoI (x, y, z, w) has the components of the Hamilton body-to-world
  // quaternion, reordered (docs/openvins.md).
  const Eigen::Vector4d jpl = ToFixed<4, 1>(q_GtoI_xyzw, "q_GtoI_xyzw");
  return RotationFromQuaternion(Eigen::Vector4d(jpl[3], jpl[0], jpl[1], jpl[2]), "q_GtoI_xyzw");
}

Vec3 OrZero(py::handle obj, const char* name) {
  return obj.is_none() ? Vec3::Zero() : ToFixed<3, 1>(obj, name);
}

template <typename T>
void Vec3Property(py::class_<T>& c, const char* name, Vec3 T::*member, const char* doc) {
  c.def_property(
      name, [member](const T& s) { return ToArray(s.*member); },
      [member, name](T& s, py::handle v) { s.*member = ToFixed<3, 1>(v, name); }, doc);
}

}  // namespace

std::string VecText(const Vec3& v) {
  return "[" + Num(v[0]) + ", " + Num(v[1]) + ", " + Num(v[2]) + "]";
}

std::string Labels(const std::vector<std::string>& labels) {
  std::string t = "[";
  for (std::size_t i = 0; i < labels.size(); ++i) t += (i ? ", '" : "'") + labels[i] + "'";
  return t + "]";
}

std::string IncrementText(const PreintIncrement& d) {
  // The rotation as an angle about an axis: what a reader checks first (the note's Exp(dtheta)).
  const Vec3 phi = so3::Log(d.dR);
  const double angle = phi.norm();
  std::string t = "rotation " + Num(angle * 180.0 / M_PI) + " deg";
  if (angle > 0.0) t += " about " + VecText(phi / angle);
  t += ", dp=" + VecText(d.dp) + ", dv=" + VecText(d.dv);
  if (!d.dbg.isZero(0.0) || !d.dba.isZero(0.0))
    t += ", dbg=" + VecText(d.dbg) + ", dba=" + VecText(d.dba);
  return t;
}

void BindValues(py::module_& m) {
  py::class_<ImuState> state(
      m, "State",
      "The 15-dof IMU state: body-to-world rotation, position and velocity of the body in the "
      "world frame, gyroscope and accelerometer biases.");
  state.def(py::init([](py::handle p, py::handle q_wxyz, py::handle v, py::handle bg, py::handle ba,
                        py::handle R, py::handle q_GtoI_xyzw) {
              ImuState x;
              x.R = OneRotation(q_wxyz, R, q_GtoI_xyzw, "State");
              x.p = OrZero(p, "p");
              x.v = OrZero(v, "v");
              x.bg = OrZero(bg, "bg");
              x.ba = OrZero(ba, "ba");
              return x;
            }),
            py::kw_only(), py::arg("p") = py::none(), py::arg("q_wxyz") = py::none(),
            py::arg("v") = py::none(), py::arg("bg") = py::none(), py::arg("ba") = py::none(),
            py::arg("R") = py::none(), py::arg("q_GtoI_xyzw") = py::none(),
            "State(*, p, q_wxyz | R | q_GtoI_xyzw, v, bg, ba). q_wxyz is Hamilton, body to world "
            "(unit within "
            "1e-6); R the body-to-world rotation matrix; q_GtoI_xyzw OpenVINS's JPL quaternion as "
            "it stores it. "
            "p, v, bg, ba default to zero.");
  state.def_property(
      "R", [](const ImuState& s) { return ToArray(s.R); },
      [](ImuState& s, py::handle R) { s.R = CheckedRotation(R, "R"); },
      "body-to-world rotation matrix (3, 3)");
  state.def_property_readonly(
      "q_wxyz",
      [](const ImuState& s) { return ToArray(Eigen::Vector4d(so3::ToQuaternionWxyz(s.R))); },
      "Hamilton quaternion [w, x, y, z] of R, w >= 0");
  Vec3Property(state, "p", &ImuState::p, "position of the body in the world (3,)");
  Vec3Property(state, "v", &ImuState::v, "velocity of the body in the world (3,)");
  Vec3Property(state, "bg", &ImuState::bg, "gyroscope bias (3,)");
  Vec3Property(state, "ba", &ImuState::ba, "accelerometer bias (3,)");
  state.def("__repr__", [](const ImuState& s) {
    const Eigen::Vector4d q = so3::ToQuaternionWxyz(s.R);
    auto vec = [](auto&& v) {
      std::string t = "[";
      for (Eigen::Index i = 0; i < v.size(); ++i) t += (i ? ", " : "") + Num(v[i]);
      return t + "]";
    };
    return "State(p=" + vec(s.p) + ", q_wxyz=" + vec(q) + ", v=" + vec(s.v) + ", bg=" + vec(s.bg) +
           ", ba=" + vec(s.ba) + ")";
  });

  py::class_<PreintIncrement> inc(
      m, "Increment",
      "A preintegrated increment: rotation dR, position dp and velocity dv in the start "
      "body frame, and the accumulated bias random walk dbg, dba (zero as an estimate).");
  inc.def(py::init([](py::handle dR, py::handle q_wxyz, py::handle dp, py::handle dv) {
            PreintIncrement d;
            d.dR = OneRotation(q_wxyz, dR, py::none(), "Increment");
            d.dp = OrZero(dp, "dp");
            d.dv = OrZero(dv, "dv");
            return d;
          }),
          py::kw_only(), py::arg("dR") = py::none(), py::arg("q_wxyz") = py::none(),
          py::arg("dp") = py::none(), py::arg("dv") = py::none(),
          "Increment(*, dR | q_wxyz, dp, dv)");
  inc.def_property(
      "dR", [](const PreintIncrement& d) { return ToArray(d.dR); },
      [](PreintIncrement& d, py::handle R) { d.dR = CheckedRotation(R, "dR"); },
      "rotation increment (3, 3)");
  inc.def_property_readonly("q_wxyz", [](const PreintIncrement& d) {
    return ToArray(Eigen::Vector4d(so3::ToQuaternionWxyz(d.dR)));
  });
  Vec3Property(inc, "dp", &PreintIncrement::dp, "position increment (3,)");
  Vec3Property(inc, "dv", &PreintIncrement::dv, "velocity increment (3,)");
  Vec3Property(inc, "dbg", &PreintIncrement::dbg, "gyroscope bias random walk (3,)");
  Vec3Property(inc, "dba", &PreintIncrement::dba, "accelerometer bias random walk (3,)");
  inc.def("__repr__",
          [](const PreintIncrement& d) { return "Increment(" + IncrementText(d) + ")"; });
}

ImuNoise ReadNoise(py::handle noise) {
  if (noise.is_none())
    throw py::value_error(
        "noise: required (a dict with gyro_noise_density, accel_noise_density, gyro_random_walk, "
        "accel_random_walk)");
  if (!py::isinstance<py::dict>(noise)) throw py::value_error("noise: expected a dict");
  const py::dict d = py::reinterpret_borrow<py::dict>(noise);
  ImuNoise q;
  const std::pair<const char*, double*> fields[] = {{"gyro_noise_density", &q.gyro_noise_density},
                                                    {"accel_noise_density", &q.accel_noise_density},
                                                    {"gyro_random_walk", &q.gyro_random_walk},
                                                    {"accel_random_walk", &q.accel_random_walk}};
  for (auto item : d) {
    const std::string key = py::str(item.first);
    bool known = false;
    for (const auto& f : fields) known |= key == f.first;
    if (!known)
      throw py::value_error("noise: unknown key '" + key +
                            "' (expected gyro_noise_density, accel_noise_density, "
                            "gyro_random_walk, accel_random_walk)");
  }
  for (const auto& [key, out] : fields) {
    if (!d.contains(key)) throw py::value_error(std::string("noise: missing '") + key + "'");
    double value;
    try {
      value = d[key].cast<double>();
    } catch (const py::cast_error&) {
      throw py::value_error(std::string("noise['") + key + "']: expected a number");
    }
    if (!std::isfinite(value) || value < 0.0)
      throw py::value_error(std::string("noise['") + key +
                            "']: expected a finite number >= 0, got " + Num(value));
    *out = value;
  }
  return q;
}

std::vector<ImuSample> ReadSamples(py::handle samples, bool allow_gaps) {
  const Float64Array a = AsFloat64(samples, "samples");
  if (a.ndim() != 2 || a.shape(1) != 7 || a.shape(0) < 2)
    throw py::value_error(
        "samples: expected shape (N, 7) with N >= 2 (rows t, wx, wy, wz, ax, ay, az), got " +
        ShapeText(a));
  std::vector<ImuSample> out(static_cast<std::size_t>(a.shape(0)));
  const double* r = a.data();
  for (std::size_t k = 0; k < out.size(); ++k, r += 7) {
    out[k].t = r[0];
    out[k].gyro = Vec3(r[1], r[2], r[3]);
    out[k].accel = Vec3(r[4], r[5], r[6]);
  }
  // The pipeline's checks (finite, increasing, rate, gaps), with its sentences.
  pipeline::TimingPolicy policy;
  policy.allow_gaps = allow_gaps;
  if (const auto issue = pipeline::FindSampleIssue(out, policy, pipeline::TimeUnit::s,
                                                   pipeline::TimeSource::imu_array))
    throw py::value_error(
        "samples: " +
        (issue->index ? "row " + std::to_string(*issue->index) + ": " : std::string()) +
        issue->message);
  return out;
}

void RequireUsableNoise(const ImuNoise& noise, const std::vector<ImuSample>& samples) {
  double shortest = samples.at(1).t - samples[0].t;
  for (std::size_t k = 2; k < samples.size(); ++k)
    shortest = std::min(shortest, samples[k].t - samples[k - 1].t);
  if (const auto issue = pipeline::FindNoiseIssue(noise, shortest))
    throw py::value_error("noise: " + *issue);
}

void WarnIfImplausible(const std::vector<ImuSample>& samples) {
  for (const auto& w : pipeline::ImuPlausibilityWarnings(samples, "samples"))
    if (PyErr_WarnEx(PyExc_UserWarning, ("imuconv: " + w).c_str(), 1) != 0)
      throw py::error_already_set();  // warnings turned into errors
}

bool IsPathArgument(py::handle h) {
  return py::isinstance<py::str>(h) || py::isinstance<py::bytes>(h) ||
         py::isinstance(h, py::module_::import("os").attr("PathLike"));
}

std::string PathArgument(py::handle h, const char* name) {
  if (!IsPathArgument(h))
    throw py::value_error(std::string(name) +
                          ": expected a path (str, bytes or os.PathLike), got " +
                          std::string(py::str(py::type::of(h).attr("__name__"))));
  std::string path;
  try {
    // os.fsencode: the bytes the file system takes, for str (surrogate escapes kept), bytes
    // and a PathLike whose __fspath__ gives either.
    path = py::module_::import("os").attr("fsencode")(h).cast<std::string>();
  } catch (py::error_already_set& e) {
    if (!e.matches(PyExc_TypeError)) throw;
    throw py::value_error(std::string(name) + ": " + std::string(py::str(e.value())));
  }
  // The C library would stop at a NUL and use a different, shorter path.
  if (path.find('\0') != std::string::npos)
    throw py::value_error(std::string(name) + ": the path contains a NUL character");
  return path;
}

}  // namespace imuconv::python
