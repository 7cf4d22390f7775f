// The entry points of the preintegration kernel (kernels/preintegration.h): the input
// checks, the instance the CPU runs (dispatch.cpp), and the change from the kernel's
// chart to the plugins' conventions. Compiled for the baseline instruction set: only the
// recursion itself runs in the wider instances.
#include <cmath>
#include <string>

#include "imuconv/so3.h"
#include "imuconv/window.h"
#include "instances.h"
#include "portable.h"

namespace imuconv::kernels {
namespace {

/// 0 for finite data; NaN if any entry is NaN or infinite (0 * inf = NaN).
double NonFiniteProbe(const ImuSample& s) {
  return 0.0 * s.t + 0.0 * s.gyro.x() + 0.0 * s.gyro.y() + 0.0 * s.gyro.z() + 0.0 * s.accel.x() +
         0.0 * s.accel.y() + 0.0 * s.accel.z();
}

void FillCommon(const PreintegrationInput& in, double dt, Preintegrated& out) {
  out.dt = dt;
  out.delta.dbg.setZero();
  out.delta.dba.setZero();
  out.bg_hat = in.bg;
  out.ba_hat = in.ba;
}

Status UnavailableIsa(Isa isa) {
  return Status::Error(
      std::string("the ") + (isa == Isa::kAvx512 ? "AVX-512" : "AVX2") +
      " instance of the preintegration kernel is not in this build or does not run on this CPU");
}

}  // namespace

Status CheckPreintegrationInput(const PreintegrationInput& in) {
  const SampleWindow& w = in.window;
  if (w.end < w.begin || w.size() < 2) return Status::Error("window has fewer than 2 knots");
  if (w.end > w.begin && w.samples == nullptr)
    return Status::Error("window has interior knots but no samples");
  if (!in.bg.allFinite() || !in.ba.allFinite()) return Status::Error("bias estimate is not finite");
  const ImuNoise& n = in.noise;
  for (double q :
       {n.gyro_noise_density, n.accel_noise_density, n.gyro_random_walk, n.accel_random_walk})
    if (!(std::isfinite(q) && q >= 0.0))
      return Status::Error("noise densities must be finite and non-negative");
  // One pass without branches over the knots; the error, if any, is located afterwards.
  double probe = NonFiniteProbe(w.first) + NonFiniteProbe(w.last);
  bool increasing = true;
  double t_prev = w.first.t;
  for (std::size_t i = w.begin; i < w.end; ++i) {
    const ImuSample& s = w.samples[i];
    probe += NonFiniteProbe(s);
    increasing &= s.t > t_prev;
    t_prev = s.t;
  }
  increasing &= w.last.t > t_prev;
  if (probe == 0.0 && increasing) return Status::Ok();
  const std::size_t count = w.size();
  for (std::size_t j = 0; j < count; ++j) {
    const ImuSample& s = w[j];
    if (!std::isfinite(s.t) || !s.gyro.allFinite() || !s.accel.allFinite())
      return Status::Error("knot " + std::to_string(j) + " of the window is not finite");
    if (j > 0 && !(s.t > w[j - 1].t))
      return Status::Error("knot times must increase strictly (knot " + std::to_string(j) + ")");
  }
  return Status::Error("window data are not finite");  // not reached: the scan above finds it
}

namespace {
/// What both schemes check before integrating: an instance this CPU runs, then the input.
/// `simd` is set to the instance to run (null: the portable path).
Status Admit(const PreintegrationInput& in, Isa isa, const detail::Instance*& simd) {
  if (!IsaAvailable(isa)) return UnavailableIsa(isa);
  simd = detail::SimdInstance(detail::ResolveIsa(isa));
  return CheckPreintegrationInput(in);
}
}  // namespace

Status IntegrateManifold(const PreintegrationInput& in, Preintegrated& out,
                         ManifoldIncrement* increment, Isa isa, bool covariance) {
  const detail::Instance* simd = nullptr;
  if (Status st = Admit(in, isa, simd); !st.ok()) return st;
  ManifoldIncrement inc;
  if (!simd) {
    detail::ManifoldPortable(in, covariance, inc, out.J_bias, out.cov);
    if (!covariance) out.cov.setZero();
  } else {
    Mat15 S;
    simd->manifold(in, Hold::Euler, inc, out.J_bias, covariance ? &S : nullptr);
    // Start-frame chart -> NavState chart / right rotation perturbation: phi = dR dtheta and
    // dp_start = dR dp_nav, i.e. T = blockdiag(dR^T, dR^T, dR^T) on the 9 increment rows.
    const Mat3 Rt = inc.dR.transpose();
    out.J_bias.topRows<3>() = Rt * out.J_bias.topRows<3>();
    if (covariance) {
      for (int b = 0; b < 9; b += 3) S.middleRows<3>(b) = Rt * S.middleRows<3>(b);
      for (int b = 0; b < 9; b += 3) S.middleCols<3>(b) = S.middleCols<3>(b) * inc.dR;
      out.cov = 0.5 * (S + S.transpose());  // rows and columns were rotated in separate roundings
    } else {
      out.cov.setZero();
    }
  }
  FillCommon(in, inc.dt, out);
  out.delta.dR = inc.dR;
  out.delta.dp = inc.dp;
  out.delta.dv = inc.dv;
  if (increment) *increment = inc;
  return Status::Ok();
}

Status IntegrateTangent(const PreintegrationInput& in, Preintegrated& out,
                        TangentIncrement* increment, Isa isa, bool covariance) {
  const detail::Instance* simd = nullptr;
  if (Status st = Admit(in, isa, simd); !st.ok()) return st;
  TangentIncrement inc;
  if (!simd)
    detail::TangentPortable(in, covariance, inc, out.J_bias, out.cov);
  else
    simd->tangent(in, inc, out.J_bias, covariance ? &out.cov : nullptr);
  if (!covariance) out.cov.setZero();
  FillCommon(in, inc.dt, out);
  out.delta.dR = so3::Exp(inc.xi.segment<3>(0));
  out.delta.dp = inc.xi.segment<3>(3);
  out.delta.dv = inc.xi.segment<3>(6);
  if (increment) *increment = inc;
  return Status::Ok();
}

Status IntegrateManifoldStartFrame(const PreintegrationInput& in, Hold hold, bool covariance,
                                   Isa isa, StartFrameManifold& out) {
  if (!IsaAvailable(isa)) return UnavailableIsa(isa);
  out.increment = ManifoldIncrement();
  const detail::Instance* simd = detail::SimdInstance(detail::ResolveIsa(isa));
  if (simd)
    simd->manifold(in, hold, out.increment, out.J_inc_bias, covariance ? &out.cov : nullptr);
  else
    detail::ManifoldStartFramePortable(in, hold, covariance, out);
  return Status::Ok();
}

}  // namespace imuconv::kernels
