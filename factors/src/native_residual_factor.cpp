// NativeResidualFactor: PreintegrationFactor's measurement (held, not copied), expressed in a
// residual plugin's increment convention, judged by the plugin's own factor; its declared
// Jacobian columns carried to the left chart, its declared weighting fixed per measurement.
#include "imuconv/ceres/native_residual_factor.h"

#include <Eigen/Eigenvalues>
#include <cstring>
#include <limits>
#include <utility>

#include "imuconv/bridge.h"
#include "imuconv/prediction.h"
#include "imuconv/residual_cost_outputs.h"
#include "sqrt_information.h"

namespace imuconv::ceres_factors {

struct NativeResidualFactor::Native {
  std::shared_ptr<const ResidualFactor> factor;
  std::string increment_convention;
  ResidualCostOutputs outputs;
  Preintegrated expressed;  ///< the measurement in increment_convention
  Eigen::MatrixXd S;        ///< n x n
  bool usable = false;      ///< false after a re-integration whose whitening failed
};

namespace {

std::string Prefix(const std::string& id) { return "native residual factor '" + id + "': "; }

std::string SafeId(const ResidualFactor* f) {
  if (f == nullptr) return "(none)";
  const char* id = f->id();
  if (id == nullptr) return "(null id)";
  return std::string(id, strnlen(id, 256));
}

std::shared_ptr<const ResidualFactor> LookUp(const Registry& reg, std::string_view id) {
  try {
    return reg.residual_factor(id);
  } catch (const Error& e) {
    throw Error(Prefix(std::string(id)) + e.what());
  }
}

PreintegrationFactor Preintegration(const std::string& id, const Registry& reg,
                                    const PreintegrationMethod& method,
                                    std::vector<ImuSample> samples, double t_s, double t_e,
                                    const ImuNoise& noise, const Vec3& bg_hat, const Vec3& ba_hat,
                                    const PreintegrationFactorOptions& options) {
  try {
    return PreintegrationFactor(reg, method, std::move(samples), t_s, t_e, noise, bg_hat, ba_hat,
                                options);
  } catch (const Error& e) {
    throw Error(Prefix(id) + e.what());
  }
}

// S with S^T S = I for a symmetric positive semi-definite information I: S = Lambda^1/2 V^T
// from I = V Lambda V^T. The cost r^T I r sees only I's symmetric part, which is what is
// decomposed. An eigenvalue below zero by no more than the solver's round-off (about
// n eps lambda_max; 64 n eps lambda_max leaves a margin) is taken as 0; below that, I is not
// semi-definite and no square root exists.
Eigen::MatrixXd SqrtOfInformation(const Eigen::MatrixXd& information) {
  const Eigen::MatrixXd I = 0.5 * (information + information.transpose());
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(I);
  if (es.info() != Eigen::Success) throw Error("its information has no eigen-decomposition");
  const Eigen::VectorXd& lambda = es.eigenvalues();  // ascending
  const double top = lambda[lambda.size() - 1];
  const double round_off =
      64.0 * static_cast<double>(I.rows()) * std::numeric_limits<double>::epsilon() * top;
  if (!(top > 0.0) || lambda[0] < -round_off)
    throw Error("its information is not positive semi-definite (eigenvalues " +
                std::to_string(lambda[0]) + " to " + std::to_string(top) + ")");
  const Eigen::VectorXd root = lambda.cwiseMax(0.0).cwiseSqrt();
  return root.asDiagonal() * es.eigenvectors().transpose();
}

// S with S^T S = C^-1 (sqrt_information.h), as PreintegrationFactor's. An S that overflows is
// the caller's "not a finite matrix", as any weighting's.
Eigen::MatrixXd SqrtOfCovarianceInverse(const Eigen::MatrixXd& C) {
  Eigen::MatrixXd S;
  if (detail::InverseCholeskyFactor(C, S) == detail::SqrtInformationStatus::kNotPositiveDefinite)
    throw Error("the measurement's covariance (its leading " + std::to_string(C.rows()) + "x" +
                std::to_string(C.cols()) +
                " block) is not positive definite (are all four noise densities positive?)");
  return S;
}

}  // namespace

NativeResidualFactor::NativeResidualFactor(const Registry& reg, std::string_view residual_id,
                                           const PreintegrationMethod& method,
                                           std::vector<ImuSample> samples, double t_s, double t_e,
                                           const ImuNoise& noise, const Vec3& bg_hat,
                                           const Vec3& ba_hat,
                                           const PreintegrationFactorOptions& options)
    : NativeResidualFactor(reg, LookUp(reg, residual_id), method, std::move(samples), t_s, t_e,
                           noise, bg_hat, ba_hat, options) {}

NativeResidualFactor::NativeResidualFactor(const Registry& reg,
                                           std::shared_ptr<const ResidualFactor> factor,
                                           const PreintegrationMethod& method,
                                           std::vector<ImuSample> samples, double t_s, double t_e,
                                           const ImuNoise& noise, const Vec3& bg_hat,
                                           const Vec3& ba_hat,
                                           const PreintegrationFactorOptions& options)
    : id_(SafeId(factor.get())),
      preintegration_(Preintegration(id_, reg, method, std::move(samples), t_s, t_e, noise, bg_hat,
                                     ba_hat, options)),
      native_(std::make_unique<Native>()) {
  try {
    if (!factor) throw Error("no residual factor was given");
    native_->factor = std::move(factor);
    const char* conv = native_->factor->increment_convention();
    if (conv == nullptr) throw Error("its increment_convention() is null");
    native_->increment_convention.assign(conv, strnlen(conv, 256));
    native_->outputs = ResolveResidualCost(reg, *native_->factor);
    ReadWhitening();
  } catch (const Error& e) {
    throw Error(Prefix(id_) + e.what());
  }
}

NativeResidualFactor::~NativeResidualFactor() = default;

int NativeResidualFactor::dimension() const { return native_->outputs.n; }

const Preintegrated& NativeResidualFactor::expressed_measurement() const {
  return native_->expressed;
}

const Eigen::MatrixXd& NativeResidualFactor::sqrt_information() const { return native_->S; }

void NativeResidualFactor::ReadWhitening() {
  Native& nv = *native_;
  nv.usable = false;
  const Registry& reg = preintegration_.registry();
  const Preintegrated& m = preintegration_.measurement();
  const Vec3& gravity = preintegration_.options().gravity;
  Preintegrated expressed = Express(reg, m, nv.increment_convention);
  // At the measurement's own prediction, as PreintegrationFactor's whitening: a start state at
  // the identity with the integration bias and the end state f(x_s, Delta x_se). Every weighting
  // a system declares is a function of the measurement alone (its covariance), so this is the
  // weighting at any pair of states.
  ImuState x_s;
  x_s.bg = m.bg_hat;
  x_s.ba = m.ba_hat;
  const ImuState x_e = Predict(x_s, m.delta, m.dt, gravity);
  ResidualOutputValues values;
  const std::string problem =
      EvaluateResidualCost(*nv.factor, nv.outputs, expressed, x_s, x_e, gravity, values);
  if (!problem.empty())
    throw Error("at the measurement's prediction over [" +
                std::to_string(preintegration_.t_start()) + ", " +
                std::to_string(preintegration_.t_end()) + "] s: " + problem);
  const int n = nv.outputs.n;
  if (nv.outputs.weighting_output >= 0 && values.values[nv.outputs.weighting_output].cols() != n)
    throw Error("its weighting '" + nv.outputs.names[nv.outputs.weighting_output] + "' is " +
                std::to_string(n) + "x" +
                std::to_string(values.values[nv.outputs.weighting_output].cols()) + " (expected " +
                std::to_string(n) + "x" + std::to_string(n) + ")");
  Eigen::MatrixXd S;
  switch (nv.outputs.weighting) {
    case ResidualWeighting::SqrtInformation:
      S = values.values[nv.outputs.weighting_output];
      break;
    case ResidualWeighting::Information:
      S = SqrtOfInformation(values.values[nv.outputs.weighting_output]);
      break;
    case ResidualWeighting::MeasurementCovariance:
      if (n > 15)
        throw Error("its residual has " + std::to_string(n) +
                    " rows, more than the measurement's covariance (15)");
      S = SqrtOfCovarianceInverse(expressed.cov.topLeftCorner(n, n));
      break;
  }
  if (S.rows() != n || S.cols() != n || !S.allFinite())
    throw Error("its whitening is not a finite " + std::to_string(n) + "x" + std::to_string(n) +
                " matrix");
  nv.expressed = std::move(expressed);
  nv.S = std::move(S);
  nv.usable = true;
}

std::string NativeResidualFactor::EvaluateOrSay(const ImuState& x_s, const ImuState& x_e,
                                                bool jacobians, Evaluation& out) const {
  const Native& nv = *native_;
  if (!nv.usable) return "its last re-integration failed; the factor is not usable";
  ResidualOutputValues values;
  const std::string problem = EvaluateResidualCost(*nv.factor, nv.outputs, nv.expressed, x_s, x_e,
                                                   preintegration_.options().gravity, values);
  if (!problem.empty()) return problem;
  out.residual = values.values[0].col(0);
  out.whitened = nv.S * out.residual;
  if (!jacobians) return "";
  // The system's Jacobian in its declared convention C, times J_{C<-left}(x): the derivative by
  // the left chart's perturbation (the chain rule through d_C = J_{C<-left} d_left).
  const Registry& reg = preintegration_.registry();
  const std::string& C = nv.outputs.state_convention;
  Eigen::MatrixXd H;
  AssembleResidualJacobian(nv.outputs, values, nv.outputs.start, H);
  out.H_start = nv.S * (H * reg.from_reference<ImuState>(C, x_s));
  AssembleResidualJacobian(nv.outputs, values, nv.outputs.end, H);
  out.H_end = nv.S * (H * reg.from_reference<ImuState>(C, x_e));
  if (!out.H_start.allFinite() || !out.H_end.allFinite())
    return "its Jacobians in the left chart are not finite";
  return "";
}

NativeResidualFactor::Evaluation NativeResidualFactor::Evaluate(const ImuState& x_s,
                                                                const ImuState& x_e) const {
  Evaluation out;
  const std::string problem = EvaluateOrSay(x_s, x_e, true, out);
  if (!problem.empty()) throw Error(Prefix(id_) + problem);
  return out;
}

bool NativeResidualFactor::EvaluateInto(const ImuState& x_s, const ImuState& x_e, bool jacobians,
                                        Evaluation& out) const noexcept {
  try {
    return EvaluateOrSay(x_s, x_e, jacobians, out).empty() && out.whitened.allFinite();
  } catch (...) {
    return false;
  }
}

bool NativeResidualFactor::ReintegrateIfMoved(const Vec3& bg, const Vec3& ba) {
  bool moved = false;
  try {
    moved = preintegration_.ReintegrateIfMoved(bg, ba);
    if (moved) ReadWhitening();
  } catch (const Error& e) {  // ReadWhitening left the factor unusable if it failed
    throw Error(Prefix(id_) + e.what());
  }
  return moved;
}

void NativeResidualFactor::Reintegrate(const Vec3& bg, const Vec3& ba) {
  try {
    preintegration_.Reintegrate(bg, ba);
    ReadWhitening();
  } catch (const Error& e) {  // ReadWhitening left the factor unusable if it failed
    throw Error(Prefix(id_) + e.what());
  }
}

}  // namespace imuconv::ceres_factors
