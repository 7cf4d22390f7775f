// "residual": the residual of a measurement between two states, with its Jacobians and
// squared Mahalanobis distance. Two output forms:
//  - kinds "gtsam" and "forster" (the bridge's generic Residual): r, H_start, H_end and
//    H_increment in charts imuconv names, the Jacobians in the task's state convention;
//  - kinds "vins_fusion" and "basalt": the system's own factor, in its own layout and
//    parameter increments, as its optimizer receives it (kernels/vins_fusion_residual.h,
//    kernels/basalt_residual.h). Their Jacobians are not w.r.t. a 15-dof state chart (VINS's
//    15x7 pose blocks with a zero q.w column, Basalt's 9-dof states without biases), so
//    forcing them into Residual's 15x15 H_start/H_end would either invent a chart or drop
//    what makes them the system's; they are written under the system's names instead, and
//    "state_convention" does not apply to them.
// The measurement is expressed in the system's increment convention (`vins_fusion`,
// `basalt`) first, so a measurement from any preintegrator can be judged by either factor.
#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <cmath>

#include "../forms/chart_matrix.h"
#include "../forms/state.h"
#include "../io/message_text.h"
#include "context.h"
#include "imuconv/kernels/basalt_residual.h"
#include "imuconv/kernels/vins_fusion_residual.h"
#include "plugins_used.h"
#include "task.h"

namespace imuconv::pipeline {
namespace {

/// The kinds written in a system's own layout rather than as a generic Residual.
enum class NativeKind { kNone, kVinsFusion, kBasalt };

/// VINS-Fusion's IntegrationBase from a measurement expressed in `vins_fusion` (the bias
/// columns of its Jacobian product are the convention's J_bias, rows [p, theta, v], columns
/// [ba, bg]; the rest of the product is not used by the factor).
kernels::VinsFusionMeasurement VinsMeasurement(const Preintegrated& m, const Vec3& gravity) {
  kernels::VinsFusionMeasurement v;
  v.pre.sum_dt = m.dt;
  v.pre.delta_p = m.delta.dp;
  v.pre.delta_v = m.delta.dv;
  v.pre.delta_q = Eigen::Quaterniond(m.delta.dR);
  v.pre.jacobian.setIdentity();
  v.pre.jacobian.block<9, 6>(0, 9) = m.J_bias;
  v.pre.covariance = m.cov;
  v.linearized_ba = m.ba_hat;
  v.linearized_bg = m.bg_hat;
  v.G = -gravity;
  return v;
}

kernels::VinsFusionFactorState VinsState(const ImuState& x) {
  kernels::VinsFusionFactorState s;
  s.P = x.p;
  s.Q = Eigen::Quaterniond(x.R);
  s.V = x.v;
  s.Ba = x.ba;
  s.Bg = x.bg;
  return s;
}

void WriteVinsOutput(JsonWriter& w, const kernels::VinsFusionFactorOutput& o) {
  w.begin_object();
  w.key("residual");
  w.vector(o.residual);
  w.key("jacobian_pose_i");
  w.matrix(o.jacobian_pose_i);
  w.key("jacobian_speedbias_i");
  w.matrix(o.jacobian_speedbias_i);
  w.key("jacobian_pose_j");
  w.matrix(o.jacobian_pose_j);
  w.key("jacobian_speedbias_j");
  w.matrix(o.jacobian_speedbias_j);
  w.end_object();
}

/// Basalt's IntegratedImuMeasurement from a measurement expressed in `basalt` (J_bias rows
/// [p, theta, v], columns [bg, ba]); its time in Basalt's integer nanoseconds.
kernels::BasaltMeasurement BasaltMeasurementOf(const Preintegrated& m) {
  kernels::BasaltMeasurement b;
  b.pre.dt_ns = std::llround(m.dt * 1e9);
  b.pre.R = m.delta.dR;
  b.pre.p = m.delta.dp;
  b.pre.v = m.delta.dv;
  b.pre.cov = m.cov.topLeftCorner<9, 9>();
  b.pre.d_state_d_bg = m.J_bias.leftCols<3>();
  b.pre.d_state_d_ba = m.J_bias.rightCols<3>();
  b.bias_gyro_lin = m.bg_hat;
  b.bias_accel_lin = m.ba_hat;
  return b;
}

kernels::BasaltPoseVelState BasaltState(const ImuState& x) {
  kernels::BasaltPoseVelState s;
  s.R = x.R;
  s.p = x.p;
  s.v = x.v;
  return s;
}

/// r^T cov^-1 r when cov is positive definite.
template <int N>
std::optional<double> Mahalanobis(const Eigen::Matrix<double, N, 1>& r,
                                  const Eigen::Matrix<double, N, N>& cov) {
  const Eigen::LDLT<Eigen::Matrix<double, N, N>> ldlt(cov);
  if (ldlt.info() != Eigen::Success || !ldlt.isPositive() || !(ldlt.vectorD().minCoeff() > 0.0))
    return std::nullopt;
  return r.dot(ldlt.solve(r));
}

class ResidualTask : public Task {
 public:
  ResidualKind kind = ResidualKind::Gtsam;
  NativeKind native = NativeKind::kNone;
  std::string kind_name;
  MeasurementsSpec meas;
  std::string convention = "left";
  StateSpec start, end;
  std::optional<std::size_t> index;

  const MeasurementsSpec* measurements() const override { return &meas; }

  void plugins_used(PluginUse& use) const override {
    if (native == NativeKind::kNone)
      use.state(convention);
    else
      use.increment(kind_name);
    use.measurements();
  }

  void check_plugins(RunContext& ctx, Checker& c) const override {
    if (native == NativeKind::kNone)
      ctx.check_id(c, PluginKind::StateConvention, convention, pointer + "/state_convention");
    else  // the measurement is expressed in the system's increment convention
      ctx.check_id(c, PluginKind::IncrementConvention, kind_name, pointer + "/kind");
  }

  ImuState state_at(const RunContext& ctx, const StateSpec& s, std::optional<double> t,
                    const char* which) const {
    if (!s.ground_truth) return s.x;
    if (!t)
      ctx.fail(s.pointer, std::string("ground truth needs the measurement's ") + which + " time");
    return ctx.gt_at(*t, s.pointer);
  }

  /// One residual of a native kind: the system's own names (anchors README) under its kind.
  std::optional<double> run_native(RunContext& ctx, JsonWriter& w, const MeasRecord& r,
                                   const ImuState& xs, const ImuState& xe) const {
    const Preintegrated m = Express(ctx.reg, r.m, kind_name);
    w.key(kind_name);
    w.begin_object();
    std::optional<double> m2;
    if (native == NativeKind::kVinsFusion) {
      const kernels::VinsFusionMeasurement v = VinsMeasurement(m, ctx.spec.gravity);
      const kernels::VinsFusionFactorState i = VinsState(xs);
      kernels::VinsFusionFactorState j = VinsState(xe);
      // A state here is a rotation matrix, a quaternion only up to sign, and VINS's rotation
      // residual 2 vec(c_q^-1 Q_i^-1 Q_j) changes sign with Q_j. In VINS-Fusion Q_j comes from
      // Q_i delta_q, so that error quaternion is near +1; Q_j's sign is chosen to make it so.
      const Eigen::Quaterniond c_q = kernels::VinsFusionCorrect(v, i.Ba, i.Bg).delta_q;
      if ((c_q.inverse() * (i.Q.inverse() * j.Q)).w() < 0.0) j.Q.coeffs() = -j.Q.coeffs();
      const kernels::VinsFusionFactorOutput raw = kernels::VinsFusionRawFactor(v, i, j);
      w.key("raw");
      WriteVinsOutput(w, raw);
      // IMUFactor's whitening, when the covariance allows it (a measurement without noise,
      // e.g. from zero densities, has none: then only the raw factor is written).
      Mat15 sqrt_info;
      if (kernels::VinsFusionSqrtInfo(v.pre.covariance, sqrt_info).ok()) {
        const kernels::VinsFusionFactorOutput white = kernels::VinsFusionWhiten(raw, sqrt_info);
        w.key("sqrt_info");
        w.matrix(sqrt_info);
        w.key("whitened");
        WriteVinsOutput(w, white);
        m2 = white.residual.squaredNorm();
      }
    } else {
      const kernels::BasaltMeasurement b = BasaltMeasurementOf(m);
      const kernels::BasaltResidual res = kernels::BasaltResidualOf(
          b, BasaltState(xs), ctx.spec.gravity, BasaltState(xe), xs.bg, xs.ba);
      w.key("residual");
      w.vector(res.residual);
      w.key("d_res_d_state0");
      w.matrix(res.d_res_d_state0);
      w.key("d_res_d_state1");
      w.matrix(res.d_res_d_state1);
      w.key("d_res_d_bg");
      w.matrix(res.d_res_d_bg);
      w.key("d_res_d_ba");
      w.matrix(res.d_res_d_ba);
      m2 = Mahalanobis<9>(res.residual, b.pre.cov);
    }
    w.end_object();
    return m2;
  }

  /// What a native kind's numbers are: written once per task.
  void write_native_layout(JsonWriter& w) const {
    w.key("layout");
    if (native == NativeKind::kVinsFusion)
      w.string(
          "VINS-Fusion IMUFactor::Evaluate: residual [p, theta, v, ba, bg] "
          "(IntegrationBase::evaluate); "
          "jacobian_pose_i/j 15x7 w.r.t. PoseLocalParameterization (p + dp, q (x) [1, dtheta/2] "
          "normalized), "
          "columns [dp, dtheta, 0]; jacobian_speedbias_i/j 15x9, columns [v, ba, bg]; raw "
          "(sqrt_info = I) and "
          "whitened by sqrt_info = LLT(cov^-1).L^T; state i = x_s (its biases the current "
          "estimate), j = x_e; "
          "the measurement expressed in vins_fusion, G = -gravity");
    else
      w.string(
          "Basalt IntegratedImuMeasurement::residual: residual [trans, rot, vel]; d_res_d_state0/1 "
          "9x9 w.r.t. "
          "PoseVelState::applyInc (p + dp, Exp(dtheta) R, v + dv); d_res_d_bg, d_res_d_ba 9x3; "
          "state0 = x_s "
          "with curr_bg/ba = x_s's biases, state1 = x_e; the measurement expressed in basalt");
  }

  /// One residual of kind gtsam or forster: the generic form, Jacobians in `convention`.
  std::optional<double> run_generic(RunContext& ctx, JsonWriter& w, const MeasRecord& r,
                                    const ImuState& xs, const ImuState& xe) const {
    static const std::vector<std::string> rblocks = {"theta", "p", "v", "bg", "ba"};
    const std::string rconv = "residual_" + kind_name;
    const auto& sb = ctx.blocks(PluginKind::StateConvention, convention);
    const auto& ib = ctx.blocks(PluginKind::IncrementConvention, "preint_reference");
    const Residual res = ComputeResidual(ctx.reg, kind, r.m, xs, xe, convention, ctx.spec.gravity);
    w.key("r");
    WriteChartVector(w, res.r, rconv, rblocks);
    w.key("H_start");
    WriteMixed(w, res.H_start, rconv, rblocks, convention, sb);
    w.key("H_end");
    WriteMixed(w, res.H_end, rconv, rblocks, convention, sb);
    w.key("H_increment");
    WriteMixed(w, res.H_increment, rconv, rblocks, "preint_reference", ib);
    w.key("cov");
    WriteCovariance(w, res.cov, rconv, rblocks);
    return Mahalanobis<15>(res.r, res.cov);
  }

  void run(RunContext& ctx, JsonWriter& w, TaskResult&) const override {
    const auto& ms = ctx.measurements(meas);
    const auto sel = ctx.select(ms, index, pointer, MeasurementsName(meas));
    if ((!start.ground_truth || !end.ground_truth) && sel.size() > 1)
      ctx.fail(pointer, "explicit start/end states go with one measurement; give \"index\" (" +
                            MeasurementsName(meas) + " has " + std::to_string(ms.size()) + ")");
    w.key("kind");
    w.string(kind_name);
    WriteMeasurementsSource(w, meas);
    if (native == NativeKind::kNone) {
      w.key("state_convention");
      w.string(convention);
    } else {
      write_native_layout(w);
    }
    w.key("residuals");
    w.begin_array();
    double sum_m2 = 0;
    std::size_t n_m2 = 0;
    for (std::size_t k : sel) {
      const MeasRecord& r = ms[k];
      const ImuState xs = state_at(ctx, start, r.t_s, "start"),
                     xe = state_at(ctx, end, r.t_e, "end");
      w.begin_object();
      w.key("index");
      w.unsigned_integer(k);
      ctx.write_times(w, r.t_s, r.t_e);
      w.key("x_s");
      WriteState(w, xs);
      w.key("x_e");
      WriteState(w, xe);
      const std::optional<double> m2 = native == NativeKind::kNone ? run_generic(ctx, w, r, xs, xe)
                                                                   : run_native(ctx, w, r, xs, xe);
      if (m2) {
        w.key("mahalanobis_squared");
        w.number(*m2);
        sum_m2 += *m2;
        ++n_m2;
      }
      w.end_object();
    }
    w.end_array();
    if (n_m2) {
      w.key("mean_mahalanobis_squared");
      w.number(sum_m2 / static_cast<double>(n_m2));
    }
    if (std::ostream* o = ctx.summary()) {
      *o << "residual '" << name << "' (" << kind_name << "): " << sel.size() << " residual(s)";
      if (n_m2)
        *o << ", mean r^T cov^-1 r = " << Num(sum_m2 / static_cast<double>(n_m2), 4) << " ("
           << (native == NativeKind::kBasalt ? 9 : 15) << " dof)";
      *o << "\n";
    }
  }
};

}  // namespace

std::unique_ptr<Task> ParseResidual(const ParseContext& ctx, const Node& n) {
  n.expect_object({"type", "name", "description", "kind", "measurements", "state_convention",
                   "start", "end", "index"});
  auto p = std::make_unique<ResidualTask>();
  if (auto kn = n.get("kind", true))
    if (auto k = kn->one_of({"gtsam", "forster", "vins_fusion", "basalt"})) {
      p->kind_name = *k;
      p->kind = *k == "forster" ? ResidualKind::Forster : ResidualKind::Gtsam;
      p->native = *k == "vins_fusion" ? NativeKind::kVinsFusion
                  : *k == "basalt"    ? NativeKind::kBasalt
                                      : NativeKind::kNone;
    }
  if (auto m = ReadMeasurementsSpec(ctx, n)) p->meas = *m;
  if (auto s = ReadPluginId(n, "state_convention", false)) {
    p->convention = *s;
    if (p->native != NativeKind::kNone)
      n.checker().error(
          n.child_pointer("state_convention"),
          "does not apply to kind '" + p->kind_name +
              "': its Jacobians are w.r.t. the system's own parameter increments (see the output's "
              "\"layout\"); give state_convention with kind gtsam or forster only");
  }
  p->index = ReadIndex(n);
  for (auto [key, dst] :
       {std::pair<const char*, StateSpec*>{"start", &p->start}, {"end", &p->end}}) {
    if (auto sn = n.get(key, false)) {
      if (auto s = ReadStateSpec(ctx, *sn)) *dst = *s;
    } else if (ctx.has_gt) {
      dst->ground_truth = true;
      dst->pointer = n.child_pointer(key);
    } else {
      n.checker().error(n.child_pointer(key),
                        "required key is missing (there is no /ground_truth to default to)");
    }
  }
  return p;
}

}  // namespace imuconv::pipeline
