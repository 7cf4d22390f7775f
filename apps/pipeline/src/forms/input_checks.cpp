#include "input_checks.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <sstream>

#include "imuconv/did_you_mean.h"
#include "imuconv/numeric.h"
#include "imuconv/printable.h"
#include "imuconv/so3.h"

namespace imuconv::pipeline {
namespace {

std::string InputNum(double v, int precision = 10) {
  std::ostringstream o;
  o.precision(precision);
  o << v;
  return o.str();
}

}  // namespace

namespace {
/// Four numbers of unit norm (within kUnitQuaternionTol) at n, laid out as `layout` says.
std::optional<Eigen::Vector4d> UnitQuaternion(const Node& n, const char* layout) {
  const auto q = n.vector(4);
  if (!q) return std::nullopt;
  const double norm = q->norm();
  if (!(std::abs(norm - 1.0) <= kUnitQuaternionTol)) {
    n.fail(std::string("expected a unit quaternion ") + layout +
           " (norm within 1e-6 of 1), found one of norm " + InputNum(norm));
    return std::nullopt;
  }
  return Eigen::Vector4d(*q);
}
}  // namespace

std::optional<Mat3> RotationFromQuaternion(const Node& n) {
  const auto q = UnitQuaternion(n, "[w, x, y, z]");
  if (!q) return std::nullopt;
  return so3::FromQuaternionWxyz((*q)[0], (*q)[1], (*q)[2], (*q)[3]);
}

std::optional<Mat3> RotationFromJplQuaternion(const Node& n) {
  const auto q = UnitQuaternion(n, "[x, y, z, w]");
  if (!q) return std::nullopt;
  // JPL C(q) = (2 q4^2 - 1) I - 2 q4 [qv]x + 2 qv qv^T is the transpose of the Hamilton
  // matrix of the same four numbers: q_GtoI (JPL) and q_ItoG (Hamilton, body to world) are
  // one quaternion, reordered.
  return so3::FromQuaternionWxyz((*q)[3], (*q)[0], (*q)[1], (*q)[2]);
}

std::optional<Mat3> RotationFromMatrix(const Node& n) {
  const auto R = n.matrix(3, 3);
  if (!R) return std::nullopt;
  const Mat3 M = *R;
  const double err = (M.transpose() * M - Mat3::Identity()).cwiseAbs().maxCoeff();
  if (!(err <= kRotationMatrixTol) || !(M.determinant() > 0.0)) {
    n.fail("expected a rotation matrix (R^T R = I within 1e-6, det +1), found max |R^T R - I| = " +
           InputNum(err) + ", det = " + InputNum(M.determinant()));
    return std::nullopt;
  }
  return so3::Exp(so3::Log(M));
}

std::string CovarianceInputProblem(const Mat15& C, double tol) {
  // kCovarianceTol (1e-9 on the correlation scale) passes round-off of any covariance
  // computed and written in double precision and catches real defects (numeric.h); numbers
  // computed in single precision are judged at theirs (kCovarianceTolFloat32).
  std::string p = CovarianceProblem(C, tol);
  if (p.empty()) return p;
  if (p.find("eigenvalue") == std::string::npos && C.allFinite()) {
    const Mat15 sym = 0.5 * (C + C.transpose());
    const Eigen::SelfAdjointEigenSolver<Mat15> eig(sym, Eigen::EigenvaluesOnly);
    p += " (smallest eigenvalue of (C + C^T)/2: " + InputNum(eig.eigenvalues().minCoeff()) + ")";
  }
  const std::string precision =
      tol == kCovarianceTol ? ""
                            : " (judged at float32 precision, tolerance " + InputNum(tol) + ")";
  return "not a valid covariance: " + p + precision + "; nothing is repaired, fix the input";
}

bool CheckCovarianceInput(Checker& c, const std::string& pointer, const Mat15& C, double tol) {
  const std::string p = CovarianceInputProblem(C, tol);
  if (p.empty()) return true;
  c.error(pointer, p);
  return false;
}

void CheckOutputCovariance(const Mat15& C, const std::string& pointer) {
  // J S J^T and Phi P Phi^T + Q of a positive semi-definite S or P have non-negative
  // variances up to round-off, which is far below 1e-9 of the largest variance.
  const double scale = C.diagonal().cwiseAbs().maxCoeff();
  for (Eigen::Index i = 0; i < C.rows(); ++i)
    if (C(i, i) < -kCovarianceTol * scale)
      throw Error("computed a covariance with a negative variance, entry (" + std::to_string(i) +
                  ", " + std::to_string(i) + ") = " + InputNum(C(i, i)) + " (output " +
                  Printable(pointer) + "; tolerance 1e-9 of the largest variance " +
                  InputNum(scale) +
                  "). The inputs were checked, so this is a defect of imuconv or of a plugin: "
                  "please report it. No output "
                  "is written");
}

void CheckPluginId(Checker& c, const Registry& reg, PluginKind kind, const std::string& id,
                   const std::string& pointer) {
  if (reg.has(kind, id)) return;
  const char* what = kind == PluginKind::StateConvention ? "state convention"
                     : kind == PluginKind::IncrementConvention
                         ? "increment (preintegration) convention"
                     : kind == PluginKind::Propagator    ? "propagator"
                     : kind == PluginKind::Preintegrator ? "preintegrator"
                                                         : "residual";
  std::string known;
  for (const auto& k : reg.ids(kind)) known += (known.empty() ? "" : ", ") + k;
  std::string msg = std::string("unknown ") + what + " " + Quoted(id) +
                    DidYouMean(id, reg.ids(kind)) + "; known: " + known;
  // A known id of another kind is a frequent slip: say so.
  for (PluginKind k : kPluginKinds)
    if (k != kind && reg.has(k, id)) msg += " (" + Quoted(id) + " is a " + KindName(k) + ")";
  c.error(pointer, msg);
}

}  // namespace imuconv::pipeline
