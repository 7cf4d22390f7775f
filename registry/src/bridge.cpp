#include "imuconv/bridge.h"

#include <array>

#include "imuconv/conversion.h"
#include "imuconv/printable.h"
#include "imuconv/reference_charts.h"
#include "imuconv/so3.h"

namespace imuconv {
namespace {

constexpr const char* kRef = "preint_reference";

// Offsets of a chart's (theta, p, v) blocks in its own order, and of its two bias blocks.
struct ChartLayout {
  std::array<int, 3> nav;         // offsets of the non-bias blocks, in the chart's order
  std::array<int, 2> bias;        // offsets of the bias blocks, in the chart's order
  std::array<int, 2> bias_is_bg;  // 1 where that bias block is bg
};

ChartLayout Layout(const BlockLabels& labels) {
  ChartLayout l{};
  int n = 0, b = 0;
  for (int i = 0; i < 5; ++i) {
    const std::string_view s = labels[i];
    if (s == "bg" || s == "ba") {
      l.bias[b] = 3 * i;
      l.bias_is_bg[b] = (s == "bg");
      ++b;
    } else {
      l.nav[n++] = 3 * i;
    }
  }
  return l;
}

// Column of the additive bias change [bg, ba] that a chart's bias column block k holds.
int RefBiasColumn(const ChartLayout& l, int k) { return l.bias_is_bg[k] ? 0 : 3; }

// A 9x6 chart-layout bias Jacobian (rows: the chart's non-bias blocks in order; columns:
// the chart's bias order) embedded into 15x6 chart rows with columns [bg, ba].
Eigen::Matrix<double, 15, 6> EmbedChartJacobian(const Mat96& J, const ChartLayout& l) {
  Eigen::Matrix<double, 15, 6> full = Eigen::Matrix<double, 15, 6>::Zero();
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 2; ++k)
      full.block<3, 3>(l.nav[r], RefBiasColumn(l, k)) = J.block<3, 3>(3 * r, 3 * k);
  return full;
}

Mat96 ExtractChartJacobian(const Eigen::Matrix<double, 15, 6>& full, const ChartLayout& l) {
  Mat96 J;
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 2; ++k)
      J.block<3, 3>(3 * r, 3 * k) = full.block<3, 3>(l.nav[r], RefBiasColumn(l, k));
  return J;
}

// Inverse of PredictJacobians' G: block diagonal with rotations, inverted by transposes.
Mat15 InversePredictG(const ImuState& xs, const PreintIncrement& d) {
  Mat15 Gi = Mat15::Zero();
  Gi.block<3, 3>(pref_idx::theta, left_idx::theta) = (xs.R * d.dR).transpose();
  Gi.block<3, 3>(pref_idx::p, left_idx::p) = xs.R.transpose();
  Gi.block<3, 3>(pref_idx::v, left_idx::v) = xs.R.transpose();
  Gi.block<3, 3>(pref_idx::bg, left_idx::bg).setIdentity();
  Gi.block<3, 3>(pref_idx::ba, left_idx::ba).setIdentity();
  return Gi;
}

Mat15 Symmetrized(const Mat15& S) { return 0.5 * (S + S.transpose()); }

// First-order bias correction in preint_reference: Delta(b) = retract_ref(Delta^, J (b - b^)).
PreintIncrement CorrectInReference(const Preintegrated& m, const Vec3& bg, const Vec3& ba) {
  Eigen::Matrix<double, 6, 1> db;
  db << bg - m.bg_hat, ba - m.ba_hat;
  Vec15 w = Vec15::Zero();
  w.head<9>() = m.J_bias * db;
  PreintIncrement out;
  PreintReferenceRetract(m.delta, w, out);
  out.dbg = m.delta.dbg;
  out.dba = m.delta.dba;
  return out;
}

// The measurement's errors are defined on the uncorrected increment Delta^; the corrected
// one is Delta^ Exp(delta) Exp(a) with a = J_theta db, and Exp(delta) Exp(a) =
// Exp(a) Exp(Exp(-a) delta), so its rotation error is Exp(a)^T delta (other blocks unchanged).
Mat15 CorrectionTransport(const Preintegrated& m, const Vec3& bg, const Vec3& ba) {
  Eigen::Matrix<double, 6, 1> db;
  db << bg - m.bg_hat, ba - m.ba_hat;
  Mat15 T = Mat15::Identity();
  T.block<3, 3>(pref_idx::theta, pref_idx::theta) =
      so3::Exp(m.J_bias.topRows<3>() * db).transpose();
  return T;
}

// Phi_e|s in the left chart (paper, section 3.2): d f / d dx_s plus [0, G^nn J_bs P_b], with
// the bias-correction curvature: the rotation rows of dR^ Exp(J_theta db) differentiate to
// Jr(J_theta db) J_theta. Columns of J_bias are [bg, ba], the left chart's bias order.
Mat15 PredictionTransition(const Preintegrated& m, const ImuState& x_s, const Mat15& F_s,
                           const Mat15& G) {
  Eigen::Matrix<double, 6, 1> db;
  db << x_s.bg - m.bg_hat, x_s.ba - m.ba_hat;
  Mat96 J = m.J_bias;
  J.topRows<3>() = so3::Jr(m.J_bias.topRows<3>() * db) * m.J_bias.topRows<3>();
  Mat15 Phi = F_s;
  Phi.block<9, 6>(0, left_idx::bg).noalias() += G.topLeftCorner<9, 9>() * J;
  return Phi;
}

}  // namespace

PreintegrationMethod ResolvePreintegrationMethod(const Registry& reg, PluginKind kind,
                                                 std::string_view id) {
  PreintegrationMethod m;
  m.id = std::string(id);
  m.kind = kind;
  if (kind == PluginKind::Propagator) {
    m.propagator = reg.propagator(id);
    m.native_state = reg.state_convention(m.propagator->native_convention());
    m.reference_state = reg.state_convention("left");
  } else if (kind == PluginKind::Preintegrator) {
    m.preintegrator = reg.preintegrator(id);
    m.cov_convention = reg.increment_convention(m.preintegrator->cov_convention());
    m.jacobian_convention = reg.increment_convention(m.preintegrator->jacobian_convention());
    m.reference_increment = reg.increment_convention(kRef);
  } else {
    throw Error("method " + Quoted(id) +
                ": a preintegration method is a propagator or a preintegrator, not a " +
                KindName(kind));
  }
  return m;
}

namespace {

Preintegrated ByPropagation(const PreintegrationMethod& method, const SampleWindow& window,
                            const Vec3& bg, const Vec3& ba, const ImuNoise& noise) {
  const PropagationInput in = PreintegrationByPropagationStart(window, bg, ba, noise);
  const PropagationResult r =
      PropagateIn(*method.propagator, *method.native_state, *method.reference_state, in);

  Preintegrated m;
  m.convention = kRef;
  m.jacobian_convention = kRef;
  m.dt = window.t_end() - window.t_start();
  m.bg_hat = bg;
  m.ba_hat = ba;
  m.delta.dR = r.x_e.R;
  m.delta.dp = r.x_e.p;
  m.delta.dv = r.x_e.v;
  m.delta.dbg = r.x_e.bg - bg;
  m.delta.dba = r.x_e.ba - ba;

  // Paper, section 3.1: J_bs = (d dx_e|s / d dx_se)^{-1} d dx_e|s / d db_s, where the direct
  // dependence of f on b_s (b_e = b_s + Delta b) is removed first; the covariance is
  // Sigma = G^{-1} cov(dx_e|s) G^{-T}.
  Mat15 F_s, G;
  PredictJacobians(in.x_s, m.delta, m.dt, &F_s, &G);
  const Mat15 Gi = InversePredictG(in.x_s, m.delta);
  const Eigen::Matrix<double, 15, 6> through_increment = r.Phi.rightCols<6>() - F_s.rightCols<6>();
  m.J_bias = (Gi * through_increment).topRows<9>();  // columns [bg, ba] = left's bias order
  m.cov = Symmetrized(Gi * r.cov * Gi.transpose());
  return m;
}

// A measurement in `cov` (J_bias rows in the chart of `jc`) brought into `ref`.
Preintegrated FromResolved(const IncrementConvention& cov, const IncrementConvention& jc,
                           const IncrementConvention& ref, const Preintegrated& in) {
  Preintegrated m = in;  // dt, delta and the bias estimate do not depend on a chart
  const Mat15 J = Conversion(cov, ref, in.delta);
  m.cov = Symmetrized(J * in.cov * J.transpose());
  const Eigen::Matrix<double, 15, 6> chart_full =
      EmbedChartJacobian(in.J_bias, Layout(jc.labels()));
  m.J_bias = (Conversion(jc, ref, in.delta) * chart_full).topRows<9>();
  m.convention = ref.id();
  m.jacobian_convention = ref.id();
  return m;
}

Preintegrated Native(const PreintegrationMethod& method, const SampleWindow& window, const Vec3& bg,
                     const Vec3& ba, const ImuNoise& noise) {
  Preintegrated native;
  const Status st =
      method.preintegrator->integrate(PreintegrationInputOf(window, bg, ba, noise), native);
  if (!st.ok()) throw Error("preintegrator " + Quoted(method.id) + ": " + Printable(st.message()));
  // The plugin wrote the numbers only (preintegrated.h); its charts are the ones it declares.
  native.convention = method.cov_convention->id();
  native.jacobian_convention = method.jacobian_convention->id();
  return FromResolved(*method.cov_convention, *method.jacobian_convention,
                      *method.reference_increment, native);
}

// `m` itself when it is in the reference charts, else its FromConvention in `converted`: the
// computations below are written in preint_reference.
const Preintegrated& InReference(const Registry& reg, const Preintegrated& m,
                                 Preintegrated& converted) {
  if (m.in_reference_charts()) return m;
  converted = FromConvention(reg, m);
  return converted;
}

}  // namespace

Preintegrated Preintegrate(const Registry& /*reg*/, const PreintegrationMethod& method,
                           const SampleWindow& window, const Vec3& bg, const Vec3& ba,
                           const ImuNoise& noise) {
  if (method.propagator) return ByPropagation(method, window, bg, ba, noise);
  if (method.preintegrator) return Native(method, window, bg, ba, noise);
  throw Error("method " + Quoted(method.id) +
              " was not resolved (use ResolvePreintegrationMethod)");
}

Preintegrated PreintegrateByPropagation(const Registry& reg, std::string_view propagator,
                                        const SampleWindow& window, const Vec3& bg, const Vec3& ba,
                                        const ImuNoise& noise) {
  return Preintegrate(reg, ResolvePreintegrationMethod(reg, PluginKind::Propagator, propagator),
                      window, bg, ba, noise);
}

Preintegrated PreintegrateNative(const Registry& reg, std::string_view preintegrator,
                                 const SampleWindow& window, const Vec3& bg, const Vec3& ba,
                                 const ImuNoise& noise) {
  return Preintegrate(reg,
                      ResolvePreintegrationMethod(reg, PluginKind::Preintegrator, preintegrator),
                      window, bg, ba, noise);
}

Preintegrated Express(const Registry& reg, const Preintegrated& given,
                      std::string_view convention) {
  Preintegrated converted;
  const Preintegrated& m = InReference(reg, given, converted);
  const auto conv = reg.increment_convention(convention);
  Preintegrated out = m;  // dt, delta and the bias estimate do not depend on a chart
  out.convention = conv->id();
  out.jacobian_convention = conv->jacobian_convention();
  const Mat15 J = reg.conversion(kRef, out.convention, m.delta);
  out.cov = Symmetrized(J * m.cov * J.transpose());

  const auto jc = reg.increment_convention(out.jacobian_convention);
  Eigen::Matrix<double, 15, 6> ref_full = Eigen::Matrix<double, 15, 6>::Zero();
  ref_full.topRows<9>() = m.J_bias;
  const Eigen::Matrix<double, 15, 6> chart_full =
      reg.conversion(kRef, out.jacobian_convention, m.delta) * ref_full;
  out.J_bias = ExtractChartJacobian(chart_full, Layout(jc->labels()));
  return out;
}

Preintegrated FromConvention(const Registry& reg, const Preintegrated& in) {
  if (in.convention.empty())
    throw Error(
        "a preintegrated measurement whose charts are not stated (its convention, the chart of "
        "cov, is "
        "empty): name the increment convention its numbers are in");
  const auto cov = reg.increment_convention(in.convention);
  const auto jc = reg.increment_convention(in.jacobian_convention.empty()
                                               ? std::string_view(cov->jacobian_convention())
                                               : std::string_view(in.jacobian_convention));
  return FromResolved(*cov, *jc, *reg.increment_convention(kRef), in);
}

PropagationResult PropagateByPreintegration(const Registry& reg, const Preintegrated& given,
                                            const ImuState& x_s, const Mat15& cov_s,
                                            std::string_view state_convention,
                                            const Vec3& gravity) {
  Preintegrated converted;
  const Preintegrated& m = InReference(reg, given, converted);
  // Paper, section 3.2: x_e|s = f(x_s, Delta x_se(b_s)), with the increment first-order
  // corrected to the start state's bias.
  const PreintIncrement delta = CorrectInReference(m, x_s.bg, x_s.ba);
  PropagationResult out;
  out.x_e = Predict(x_s, delta, m.dt, gravity);

  Mat15 F_s, G;
  PredictJacobians(x_s, delta, m.dt, &F_s, &G);
  const Mat15 Phi = PredictionTransition(m, x_s, F_s, G);

  const Mat15 S_s = reg.convert_covariance(state_convention, "left", x_s, cov_s);
  const Mat15 GT = G * CorrectionTransport(m, x_s.bg, x_s.ba);
  const Mat15 S_e = Phi * S_s * Phi.transpose() + GT * m.cov * GT.transpose();  // eq. prop-cov
  out.Phi = reg.convert_transition("left", state_convention, x_s, out.x_e, Phi);
  out.cov = reg.convert_covariance("left", state_convention, out.x_e, Symmetrized(S_e));
  return out;
}

PreintIncrement BiasCorrectedDelta(const Registry& reg, const Preintegrated& given,
                                   std::string_view jacobian_convention, const Vec3& bg,
                                   const Vec3& ba) {
  Preintegrated converted;
  const Preintegrated& m = InReference(reg, given, converted);
  const auto jc = reg.increment_convention(jacobian_convention);
  const ChartLayout l = Layout(jc->labels());
  Eigen::Matrix<double, 15, 6> ref_full = Eigen::Matrix<double, 15, 6>::Zero();
  ref_full.topRows<9>() = m.J_bias;
  const Eigen::Matrix<double, 15, 6> chart_full =
      reg.conversion(kRef, jacobian_convention, m.delta) * ref_full;
  Eigen::Matrix<double, 6, 1> db;  // [bg, ba]
  db << bg - m.bg_hat, ba - m.ba_hat;
  Vec15 w = chart_full * db;
  for (int k = 0; k < 2; ++k)
    w.segment<3>(l.bias[k]).setZero();  // the bias estimate does not move Delta b
  PreintIncrement out;
  jc->retract(m.delta, w, out);
  return out;
}

Residual ComputeResidual(const Registry& reg, ResidualKind kind, const Preintegrated& given,
                         const ImuState& x_s, const ImuState& x_e,
                         std::string_view state_convention, const Vec3& gravity) {
  using namespace left_idx;
  Preintegrated converted;
  const Preintegrated& m = InReference(reg, given, converted);
  const PreintIncrement delta = CorrectInReference(m, x_s.bg, x_s.ba);
  const ImuState xp = Predict(x_s, delta, m.dt, gravity);

  // d x_pred / d dx_s and d x_pred / d dx_se in the left chart (as in PropagateByPreintegration).
  Mat15 F_s, G;
  PredictJacobians(x_s, delta, m.dt, &F_s, &G);
  const Mat15 Phi = PredictionTransition(m, x_s, F_s, G);

  // Residual rows [theta, p, v, bg, ba]; D_pred, D_end, D_start_direct: derivatives with
  // respect to left-chart perturbations of the prediction, the end state and (directly)
  // the start state.
  Residual out;
  Mat15 D_pred = Mat15::Zero(), D_end = Mat15::Zero(), D_start = Mat15::Zero();
  const Mat3 I3 = Mat3::Identity();
  if (kind == ResidualKind::Gtsam) {
    // r_theta = Log(R_e^T R_pred), r_p = R_e^T (p_pred - p_e), r_v = R_e^T (v_pred - v_e)
    // (paper, eq. subeq:rtheta..rb; PreintegrationBase::computeError), r_b = b_e - b_pred.
    const Vec3 r_theta = so3::Log(x_e.R.transpose() * xp.R);
    const Mat3 Ret = x_e.R.transpose();
    out.r << r_theta, Ret * (xp.p - x_e.p), Ret * (xp.v - x_e.v), x_e.bg - xp.bg, x_e.ba - xp.ba;
    const Mat3 JrInv = so3::JrInv(r_theta);
    D_pred.block<3, 3>(0, theta) = JrInv * xp.R.transpose();
    D_pred.block<3, 3>(3, p) = Ret;
    D_pred.block<3, 3>(6, v) = Ret;
    D_pred.block<3, 3>(9, bg) = -I3;
    D_pred.block<3, 3>(12, ba) = -I3;
    D_end.block<3, 3>(0, theta) = -JrInv * xp.R.transpose();
    D_end.block<3, 3>(3, theta) = Ret * so3::skew(xp.p - x_e.p);
    D_end.block<3, 3>(3, p) = -Ret;
    D_end.block<3, 3>(6, theta) = Ret * so3::skew(xp.v - x_e.v);
    D_end.block<3, 3>(6, v) = -Ret;
    D_end.block<3, 3>(9, bg) = I3;
    D_end.block<3, 3>(12, ba) = I3;
  } else {
    // Forster et al.: r_theta = Log(R_pred^T R_e), r_p = R_s^T (p_e - p_pred),
    // r_v = R_s^T (v_e - v_pred), r_b = b_e - b_pred (paper, eq. subeq:rtheta-forster..).
    const Vec3 r_theta = so3::Log(xp.R.transpose() * x_e.R);
    const Mat3 Rst = x_s.R.transpose();
    out.r << r_theta, Rst * (x_e.p - xp.p), Rst * (x_e.v - xp.v), x_e.bg - xp.bg, x_e.ba - xp.ba;
    const Mat3 JrInv = so3::JrInv(r_theta);
    D_pred.block<3, 3>(0, theta) = -JrInv * x_e.R.transpose();
    D_pred.block<3, 3>(3, p) = -Rst;
    D_pred.block<3, 3>(6, v) = -Rst;
    D_pred.block<3, 3>(9, bg) = -I3;
    D_pred.block<3, 3>(12, ba) = -I3;
    D_end.block<3, 3>(0, theta) = JrInv * x_e.R.transpose();
    D_end.block<3, 3>(3, p) = Rst;
    D_end.block<3, 3>(6, v) = Rst;
    D_end.block<3, 3>(9, bg) = I3;
    D_end.block<3, 3>(12, ba) = I3;
    // R_s appears directly: R_s^T Exp(-e) a = R_s^T a + R_s^T [a]x e.
    D_start.block<3, 3>(3, theta) = Rst * so3::skew(x_e.p - xp.p);
    D_start.block<3, 3>(6, theta) = Rst * so3::skew(x_e.v - xp.v);
  }
  const Mat15 H_start_left = D_pred * Phi + D_start;
  out.H_increment = D_pred * G * CorrectionTransport(m, x_s.bg, x_s.ba);
  out.cov = Symmetrized(out.H_increment * m.cov * out.H_increment.transpose());  // eq. residual-cov
  out.H_start = H_start_left * reg.conversion(state_convention, "left", x_s);
  out.H_end = D_end * reg.conversion(state_convention, "left", x_e);
  return out;
}

}  // namespace imuconv
