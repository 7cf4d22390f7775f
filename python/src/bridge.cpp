// The bridge (the note, section 3) from Python: preintegration by any propagator or native
// preintegrator, a measurement expressed in any increment convention and imported back,
// propagation in any state convention, propagation by preintegration, residuals and bias
// correction. The computations release the GIL; arrays are copied in and out.
#include "imuconv/bridge.h"

#include <pybind11/stl.h>

#include <optional>
#include <string>
#include <vector>

#include "arrays.h"
#include "bindings.h"
#include "finite_results.h"
#include "imuconv/so3.h"

namespace imuconv::python {
namespace {

/// The window [t_start, t_end] of the samples (their first and last times by default).
SampleWindow Window(const std::vector<ImuSample>& s, std::optional<double> t_start,
                    std::optional<double> t_end) {
  const double ts = t_start.value_or(s.front().t), te = t_end.value_or(s.back().t);
  if (!std::isfinite(ts) || !std::isfinite(te))
    throw py::value_error("t_start, t_end: must be finite");
  SampleWindow w;
  const Status st = MakeWindow(s.data(), s.size(), ts, te, w);
  if (!st)
    throw py::value_error("samples: no window [" + Num(ts) + ", " + Num(te) +
                          "] s: " + st.message() + " (the samples span [" + Num(s.front().t) +
                          ", " + Num(s.back().t) + "])");
  return w;
}

/// One of propagator= and preintegrator=, resolved with the conventions its path needs.
PreintegrationMethod Method(const LoadedRegistry& r, const std::optional<std::string>& propagator,
                            const std::optional<std::string>& preintegrator) {
  if (propagator.has_value() == preintegrator.has_value())
    throw py::value_error(
        "give exactly one of propagator= (preintegration by propagation) and preintegrator= "
        "(a native scheme)");
  return propagator ? ResolvePreintegrationMethod(r, PluginKind::Propagator, *propagator)
                    : ResolvePreintegrationMethod(r, PluginKind::Preintegrator, *preintegrator);
}

template <typename T>
void ReadOnly(py::class_<T>& c, const char* name, Vec3 T::*member, const char* doc) {
  c.def_property_readonly(
      name, [member](const T& s) { return ToArray(s.*member); }, doc);
}

Vec3 Gravity(py::handle g) { return ToFixed<3, 1>(g, "gravity"); }

Expressed ExpressIn(const LoadedRegistry& r, const Preintegrated& p,
                    const std::string& convention) {
  Expressed e;
  static_cast<Preintegrated&>(e) = FiniteMeasurement(Express(r, p, convention), "express");
  e.blocks = r.info(PluginKind::IncrementConvention, convention).blocks;
  // J_bias's rows and columns follow its own chart's order (Express lays it out so).
  for (const auto& b : r.info(PluginKind::IncrementConvention, e.jacobian_convention).blocks)
    (b == "bg" || b == "ba" ? e.J_bias_columns : e.J_bias_rows).push_back(b);
  return e;
}

}  // namespace

void BindBridge(py::module_& m) {
  py::class_<Preintegrated> pre(
      m, "Preintegrated",
      "A preintegrated measurement in the reference charts (convention-free): delta and "
      "cov in preint_reference ([theta, p, v, bg, ba], dR Exp(dtheta), additive p, v, bias "
      "walk), J_bias (9, 6) d(theta, p, v) / d(bias estimate), columns [bg, ba]. "
      "express(reg, convention) gives it in any increment convention.");
  pre.def_readonly("dt", &Preintegrated::dt, "length of the interval, s");
  pre.def_readonly("delta", &Preintegrated::delta, "the increment (Increment)");
  ReadOnly(pre, "bg_hat", &Preintegrated::bg_hat,
           "gyroscope bias estimate it was integrated with (3,)");
  ReadOnly(pre, "ba_hat", &Preintegrated::ba_hat,
           "accelerometer bias estimate it was integrated with (3,)");
  pre.def_property_readonly("J_bias", [](const Preintegrated& p) { return ToArray(p.J_bias); });
  pre.def_property_readonly("cov", [](const Preintegrated& p) { return ToArray(p.cov); });
  pre.def("__repr__", [](const Preintegrated& p) {
    return "Preintegrated(dt=" + Num(p.dt) + ", " + IncrementText(p.delta) +
           ", bg_hat=" + VecText(p.bg_hat) + ", ba_hat=" + VecText(p.ba_hat) +
           "; cov (15, 15) in preint_reference ['theta', 'p', 'v', 'bg', 'ba'], J_bias (9, 6) rows "
           "['theta', 'p', "
           "'v'] columns ['bg', 'ba'])";
  });
  pre.def(
      "express",
      [](const Preintegrated& p, const LoadedRegistry& r, const std::string& convention) {
        return ExpressIn(r, p, convention);
      },
      py::arg("reg"), py::arg("convention"),
      "This measurement in a named increment convention (Expressed).");

  py::class_<Expressed> in(
      m, "Expressed",
      "A preintegrated measurement in a named increment convention, in its block order: "
      "cov in `convention`, J_bias rows in `jacobian_convention`'s (theta, p, v) blocks, "
      "columns in the convention's bias order.");
  in.def_readonly("convention", &Expressed::convention);
  in.def_readonly("jacobian_convention", &Expressed::jacobian_convention);
  in.def_readonly("dt", &Expressed::dt);
  in.def_property_readonly("delta_R", [](const Expressed& p) { return ToArray(p.delta.dR); });
  in.def_property_readonly("q_wxyz", [](const Expressed& p) {
    return ToArray(Eigen::Vector4d(so3::ToQuaternionWxyz(p.delta.dR)));
  });
  in.def_property_readonly("dp", [](const Expressed& p) { return ToArray(p.delta.dp); });
  in.def_property_readonly("dv", [](const Expressed& p) { return ToArray(p.delta.dv); });
  in.def_property_readonly("bg_hat", [](const Expressed& p) { return ToArray(p.bg_hat); });
  in.def_property_readonly("ba_hat", [](const Expressed& p) { return ToArray(p.ba_hat); });
  in.def_property_readonly("J_bias", [](const Expressed& p) { return ToArray(p.J_bias); });
  in.def_property_readonly("cov", [](const Expressed& p) { return ToArray(p.cov); });
  in.def_readonly("delta", &Expressed::delta);
  in.def_readonly("blocks", &Expressed::blocks,
                  "the block order of cov, e.g. ['theta', 'p', 'v', 'bg', 'ba']");
  in.def_readonly(
      "J_bias_rows", &Expressed::J_bias_rows,
      "the row blocks of J_bias, in jacobian_convention's order, e.g. ['theta', 'p', 'v']");
  in.def_readonly("J_bias_columns", &Expressed::J_bias_columns,
                  "the column blocks of J_bias (an additive change of the bias estimate), in "
                  "jacobian_convention's "
                  "order, e.g. ['bg', 'ba'] or ['ba', 'bg']");
  in.def("__repr__", [](const Expressed& e) {
    return "Expressed(convention='" + e.convention + "', blocks=" + Labels(e.blocks) +
           ", jacobian_convention='" + e.jacobian_convention +
           "', J_bias_rows=" + Labels(e.J_bias_rows) +
           ", J_bias_columns=" + Labels(e.J_bias_columns) + ", dt=" + Num(e.dt) + ", " +
           IncrementText(e.delta) + ")";
  });
  in.def(
      "to_preintegrated",
      [](const Expressed& e, const LoadedRegistry& r) {
        return FiniteMeasurement(FromConvention(r, e), "to_preintegrated");
      },
      py::arg("reg"), "Back to the reference charts (the inverse of Preintegrated.express).");

  py::class_<PropagationResult> prop(
      m, "Propagation",
      "A propagated state x_e with the transition Phi = d dx_e / d dx_s and the "
      "covariance cov, both in the state convention of the call.");
  prop.def_readonly("x_e", &PropagationResult::x_e);
  prop.def_property_readonly("Phi", [](const PropagationResult& p) { return ToArray(p.Phi); });
  prop.def_property_readonly("cov", [](const PropagationResult& p) { return ToArray(p.cov); });

  py::class_<Residual> res(
      m, "Residual",
      "A 15-dim residual [theta, p, v, bg, ba] with its Jacobians with respect to the start "
      "and end states (in the state convention of the call), its covariance, and H_increment "
      "= d r / d(the measured increment in preint_reference).");
  res.def_property_readonly("r", [](const Residual& x) { return ToArray(x.r); });
  res.def_property_readonly("H_start", [](const Residual& x) { return ToArray(x.H_start); });
  res.def_property_readonly("H_end", [](const Residual& x) { return ToArray(x.H_end); });
  res.def_property_readonly("cov", [](const Residual& x) { return ToArray(x.cov); });
  res.def_property_readonly("H_increment",
                            [](const Residual& x) { return ToArray(x.H_increment); });

  m.def(
      "preintegrate",
      [](const LoadedRegistry& r, py::handle samples, py::handle bg, py::handle ba,
         py::handle noise, std::optional<std::string> propagator,
         std::optional<std::string> preintegrator, std::optional<double> t_start,
         std::optional<double> t_end, bool allow_gaps) {
        const PreintegrationMethod method = Method(r, propagator, preintegrator);
        const std::vector<ImuSample> s = ReadSamples(samples, allow_gaps);
        WarnIfImplausible(s);
        const SampleWindow w = Window(s, t_start, t_end);
        const Vec3 g = ToFixed<3, 1>(bg, "bg"), a = ToFixed<3, 1>(ba, "ba");
        const ImuNoise q = ReadNoise(noise);
        RequireUsableNoise(q, s);
        py::gil_scoped_release release;
        return FiniteMeasurement(Preintegrate(r, method, w, g, a, q), "preintegrate");
      },
      py::arg("reg"), py::arg("samples"), py::kw_only(), py::arg("bg"), py::arg("ba"),
      py::arg("noise"), py::arg("propagator") = py::none(), py::arg("preintegrator") = py::none(),
      py::arg("t_start") = py::none(), py::arg("t_end") = py::none(), py::arg("allow_gaps") = false,
      "Preintegrates samples (N, 7: t, wx, wy, wz, ax, ay, az) over [t_start, t_end] (the samples' "
      "span by "
      "default; ends between samples are interpolated) with bias estimates bg, ba: by propagation "
      "with "
      "propagator= (the note, section 3.1) or natively with preintegrator=. noise: the four "
      "continuous "
      "densities. The samples get the pipeline's checks (finite, increasing t in seconds, a "
      "plausible rate, "
      "no gap beyond 10 x the median period unless allow_gaps=True); a non-finite result is a "
      "ValueError.");

  m.def(
      "from_convention",
      [](const LoadedRegistry& r, const std::string& convention, double dt,
         const PreintIncrement& delta, py::handle bg_hat, py::handle ba_hat, py::handle J_bias,
         py::handle cov, std::optional<std::string> jacobian_convention) {
        Preintegrated in;
        in.convention = convention;
        in.jacobian_convention = jacobian_convention.value_or(
            r.info(PluginKind::IncrementConvention, convention).jacobian_convention);
        if (!(std::isfinite(dt) && dt > 0.0))
          throw py::value_error("dt: expected a finite number > 0, got " + Num(dt));
        in.dt = dt;
        in.delta = delta;
        in.bg_hat = ToFixed<3, 1>(bg_hat, "bg_hat");
        in.ba_hat = ToFixed<3, 1>(ba_hat, "ba_hat");
        in.J_bias = ToFixed<9, 6>(J_bias, "J_bias");
        in.cov = CheckedCovariance(cov, "cov");
        return FiniteMeasurement(FromConvention(r, in), "from_convention");
      },
      py::arg("reg"), py::arg("convention"), py::kw_only(), py::arg("dt"), py::arg("delta"),
      py::arg("bg_hat"), py::arg("ba_hat"), py::arg("J_bias"), py::arg("cov"),
      py::arg("jacobian_convention") = py::none(),
      "Imports a measurement given in a named increment convention (e.g. numbers dumped from "
      "GTSAM): cov in "
      "`convention`'s chart and block order, J_bias rows in `jacobian_convention`'s chart (the "
      "convention's own "
      "by default).");

  m.def(
      "propagate",
      [](const LoadedRegistry& r, const std::string& propagator, const std::string& convention,
         const ImuState& x, py::handle cov, py::handle samples, py::handle noise,
         py::handle gravity, std::optional<double> t_start, std::optional<double> t_end,
         bool allow_gaps) {
        PropagationInput in;
        in.x_s = x;
        in.cov_s = CheckedCovariance(cov, "cov");
        const std::vector<ImuSample> s = ReadSamples(samples, allow_gaps);
        WarnIfImplausible(s);
        in.window = Window(s, t_start, t_end);
        in.noise = ReadNoise(noise);
        RequireUsableNoise(in.noise, s);
        in.gravity = Gravity(gravity);
        py::gil_scoped_release release;
        return FinitePropagation(r.propagate(propagator, convention, in), "propagate");
      },
      py::arg("reg"), py::arg("propagator"), py::arg("convention"), py::arg("x"), py::arg("cov"),
      py::arg("samples"), py::kw_only(), py::arg("noise"),
      py::arg("gravity") = std::vector<double>{0.0, 0.0, -9.81}, py::arg("t_start") = py::none(),
      py::arg("t_end") = py::none(), py::arg("allow_gaps") = false,
      "Propagates x with covariance cov (both in the state convention `convention`) over the "
      "samples with a "
      "propagator plugin: x_e, Phi and cov in that convention.");

  m.def(
      "propagate_by_preintegration",
      [](const LoadedRegistry& r, const Preintegrated& meas, const ImuState& x_s, py::handle cov_s,
         const std::string& convention, py::handle gravity) {
        const Mat15 S = CheckedCovariance(cov_s, "cov_s");
        const Vec3 g = Gravity(gravity);
        py::gil_scoped_release release;
        return FinitePropagation(PropagateByPreintegration(r, meas, x_s, S, convention, g),
                                 "propagate_by_preintegration");
      },
      py::arg("reg"), py::arg("m"), py::arg("x_s"), py::arg("cov_s"), py::arg("convention"),
      py::kw_only(), py::arg("gravity") = std::vector<double>{0.0, 0.0, -9.81},
      "The note, section 3.2: the prediction from a measurement, with Phi and Sigma = Phi cov_s "
      "Phi^T + G "
      "Sigma_dx G^T, in the state convention `convention`.");

  m.def(
      "residual",
      [](const LoadedRegistry& r, const std::string& kind, const Preintegrated& meas,
         const ImuState& x_s, const ImuState& x_e, const std::string& convention,
         py::handle gravity) {
        ResidualKind k;
        if (kind == "gtsam")
          k = ResidualKind::Gtsam;
        else if (kind == "forster")
          k = ResidualKind::Forster;
        else
          throw py::value_error("kind: unknown residual kind '" + kind +
                                "' (expected gtsam or forster)");
        const Vec3 g = Gravity(gravity);
        py::gil_scoped_release release;
        return FiniteResidual(ComputeResidual(r, k, meas, x_s, x_e, convention, g), "residual");
      },
      py::arg("reg"), py::arg("kind"), py::arg("m"), py::arg("x_s"), py::arg("x_e"),
      py::arg("convention"), py::kw_only(),
      py::arg("gravity") = std::vector<double>{0.0, 0.0, -9.81},
      "The residual of kind gtsam (PreintegrationBase::computeError) or forster between x_s and "
      "x_e, the start "
      "bias applied to the measurement by first-order correction; Jacobians in the state "
      "convention "
      "`convention`.");

  m.def(
      "bias_corrected_delta",
      [](const LoadedRegistry& r, const Preintegrated& meas, const std::string& jacobian_convention,
         py::handle bg, py::handle ba) {
        // A first-order correction by a bias far from the estimate (1e300 rad/s) overflows:
        // refused, as every result of the module (finite_results.h).
        return FiniteValue(BiasCorrectedDelta(r, meas, jacobian_convention, ToFixed<3, 1>(bg, "bg"),
                                              ToFixed<3, 1>(ba, "ba")),
                           "bias_corrected_delta");
      },
      py::arg("reg"), py::arg("m"), py::arg("jacobian_convention"), py::kw_only(), py::arg("bg"),
      py::arg("ba"),
      "The increment corrected to new bias estimates to first order in the chart of "
      "jacobian_convention "
      "(GTSAM's biasCorrectedDelta when that chart is GTSAM's).");
}

}  // namespace imuconv::python
