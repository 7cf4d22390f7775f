// imuconv.optimize: the keyframe estimate of `imuconv optimize` (imuconv/optimize/optimize.h) on
// arrays, returned as NumPy arrays. Built only with Ceres (python/CMakeLists.txt).
#include <pybind11/stl.h>

#include <Eigen/Geometry>
#include <cmath>
#include <string>
#include <vector>

#include "arrays.h"
#include "bindings.h"
#include "imuconv/optimize/optimize.h"
#include "imuconv/optimize/optimize_output.h"
#include "imuconv/optimize/pipeline_task.h"
#include "imuconv/pipeline/ground_truth_quaternion.h"
#include "imuconv/pipeline/imu_plausibility.h"

namespace imuconv::python {
namespace {

// (M, 8) rows t, px, py, pz, qw, qx, qy, qz, or (M, 17) EuRoC ground-truth rows (those, then v,
// bg, ba; the biases become the reference the estimate is compared with); t in seconds on the
// samples' time axis, strictly increasing.
pipeline::GroundTruth ReadPoses(py::handle poses) {
  const Float64Array a = AsFloat64(poses, "poses");
  if (a.ndim() != 2 || (a.shape(1) != 8 && a.shape(1) != 17) || a.shape(0) < 2)
    throw py::value_error(
        "poses: expected shape (M, 8) (t, p xyz, q wxyz) or (M, 17) (EuRoC: "
        "then v, bg, ba) with M >= 2, got " +
        ShapeText(a));
  RequireFinite(a.data(), a.size(), "poses");
  const auto cols = a.shape(1);
  pipeline::GroundTruth gt;
  gt.source = "poses";
  gt.full_state = cols == 17;
  gt.format = cols == 17 ? "euroc" : "euroc_pose";
  for (py::ssize_t i = 0; i < a.shape(0); ++i) {
    const double* row = a.data() + i * cols;
    if (i > 0 && !(row[0] > gt.t.back()))
      throw py::value_error("poses: row " + std::to_string(i) + ": t " + Num(row[0]) +
                            " does not increase");
    // The ground-truth readers' rule (unit within 1e-3, then normalised), so that the rows
    // `imuconv optimize --poses` accepts from a file are accepted here as arrays.
    if (const auto problem = pipeline::GroundTruthQuaternionProblem(row[4], row[5], row[6], row[7],
                                                                    "(q_w, q_x, q_y, q_z)"))
      throw py::value_error("poses: row " + std::to_string(i) + ": " + *problem);
    const Eigen::Quaterniond q(row[4], row[5], row[6], row[7]);
    ImuState x;
    x.R = q.normalized().toRotationMatrix();
    x.p = Vec3(row[1], row[2], row[3]);
    if (gt.full_state) {
      x.v = Vec3(row[8], row[9], row[10]);
      x.bg = Vec3(row[11], row[12], row[13]);
      x.ba = Vec3(row[14], row[15], row[16]);
    }
    gt.t.push_back(row[0]);
    gt.x.push_back(x);
  }
  return gt;
}

template <int N>
py::array Rows(const std::vector<optimize::Keyframe>& ks,
               Eigen::Matrix<double, N, 1> (*get)(const optimize::Keyframe&)) {
  py::array_t<double> out({static_cast<py::ssize_t>(ks.size()), static_cast<py::ssize_t>(N)});
  for (std::size_t i = 0; i < ks.size(); ++i) {
    const Eigen::Matrix<double, N, 1> v = get(ks[i]);
    for (int j = 0; j < N; ++j) out.mutable_data()[i * N + j] = v[j];
  }
  return std::move(out);
}

}  // namespace

void BindOptimize(py::module_& m) {
  optimize::RegisterPipelineTask();  // imuconv.run's optimize tasks
  m.def(
      "optimize",
      [](const LoadedRegistry& r, py::handle samples, py::handle poses, py::handle noise,
         double keyframe_step, const std::string& method, const std::string& convention,
         std::pair<double, double> pose_sigma, const std::string& residual, py::handle gravity,
         double reintegrate_gyro, double reintegrate_accel, int max_rounds) {
        if (residual != "gtsam" && residual != "forster")
          throw py::value_error("residual: expected 'gtsam' or 'forster', got '" + residual + "'");
        pipeline::ImuData imu;
        imu.samples = ReadSamples(samples, /*allow_gaps=*/false);
        imu.source = "samples";
        WarnIfImplausible(imu.samples);
        const pipeline::GroundTruth gt = ReadPoses(poses);
        for (const auto& w : pipeline::PoseGyroWarnings(imu.samples, gt, "poses"))
          if (PyErr_WarnEx(PyExc_UserWarning, ("imuconv: " + w).c_str(), 1) != 0)
            throw py::error_already_set();  // warnings turned into errors
        optimize::Options o;
        o.noise = ReadNoise(noise);
        RequireUsableNoise(o.noise, imu.samples);  // as preintegrate, propagate and the CLI
        o.method = method;
        o.convention = convention;
        o.kind = residual == "forster" ? ResidualKind::Forster : ResidualKind::Gtsam;
        o.keyframe_step = keyframe_step;
        o.pose_sigma_m = pose_sigma.first;
        o.pose_sigma_rad = pose_sigma.second;
        o.gravity = ToFixed<3, 1>(gravity, "gravity");
        o.reintegrate_gyro = reintegrate_gyro;
        o.reintegrate_accel = reintegrate_accel;
        o.max_rounds = max_rounds;
        optimize::Result res;
        {
          py::gil_scoped_release release;
          res = optimize::RunOptimize(r, imu, gt, o);
        }
        const auto& ks = res.keyframes;
        py::array_t<double> t(static_cast<py::ssize_t>(ks.size()));
        for (std::size_t i = 0; i < ks.size(); ++i) t.mutable_data()[i] = ks[i].t;
        py::dict out;
        out["t"] = t;
        out["p"] = Rows<3>(ks, [](const optimize::Keyframe& k) -> Vec3 { return k.x.p; });
        out["q_wxyz"] = Rows<4>(ks, [](const optimize::Keyframe& k) -> Eigen::Vector4d {
          return optimize::UnitQuaternionWxyz(k.x.R);
        });
        out["v"] = Rows<3>(ks, [](const optimize::Keyframe& k) -> Vec3 { return k.x.v; });
        out["bg"] = Rows<3>(ks, [](const optimize::Keyframe& k) -> Vec3 { return k.x.bg; });
        out["ba"] = Rows<3>(ks, [](const optimize::Keyframe& k) -> Vec3 { return k.x.ba; });
        if (res.covariance_ok) {
          py::array_t<double> cov(
              {static_cast<py::ssize_t>(ks.size()), py::ssize_t{15}, py::ssize_t{15}});
          for (std::size_t i = 0; i < ks.size(); ++i)
            for (int a = 0; a < 15; ++a)
              for (int b = 0; b < 15; ++b)
                cov.mutable_data()[(i * 15 + a) * 15 + b] = ks[i].cov(a, b);
          out["cov"] = cov;
        } else {
          out["cov"] = py::none();
        }
        out["blocks"] = res.labels;
        out["converged"] = res.converged;
        py::dict solver;
        solver["iterations"] = optimize::TotalIterations(res);
        solver["seconds"] = optimize::TotalSeconds(res);
        solver["message"] = res.solver_message;
        // The rounds as imuconv optimize --json lists them (a JSON document goes to Python
        // through the json module, as check's report does).
        solver["rounds"] =
            py::module_::import("json").attr("loads")(optimize::RoundsJson(res).dump());
        solver["pending_reintegration"] = res.pending_reintegration;
        solver["covariance_message"] = res.covariance_message;
        out["solver"] = solver;
        return out;
      },
      py::arg("reg"), py::arg("samples"), py::arg("poses"), py::kw_only(), py::arg("noise"),
      py::arg("keyframe_step"), py::arg("method") = "manifold", py::arg("convention") = "left",
      py::arg("pose_sigma") = std::pair<double, double>(0.01, 0.01), py::arg("residual") = "gtsam",
      py::arg("gravity") = std::vector<double>{0.0, 0.0, -9.81}, py::arg("reintegrate_gyro") = 0.01,
      py::arg("reintegrate_accel") = 0.10, py::arg("max_rounds") = 4,
      "Estimates every keyframe's state from samples (N, 7: t, wx, wy, wz, ax, ay, az; seconds) "
      "and poses (M, 8: t, p xyz, q wxyz, or M, 17: EuRoC rows with v, bg, ba; seconds on the "
      "samples' time axis) as `imuconv optimize` does: keyframes every keyframe_step seconds, "
      "preintegration factors of method, pose measurements with pose_sigma (metres, radians), "
      "solved with Ceres in the chart of convention. Returns a dict of arrays t (K,), p, v, bg, ba "
      "(K, 3), q_wxyz (K, 4), cov (K, 15, 15, in convention's block order `blocks`; None if it "
      "could not be computed), converged, and the solver summary. A solve that did not converge "
      "has converged False (its numbers are where it stopped).");
}

}  // namespace imuconv::python
