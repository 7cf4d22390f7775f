// The step specification of the preintegration kernel (kernels/preintegration.h) in plain
// Eigen: what the SIMD block recursion implements, what the portable path runs, and what
// the tests difference. Compiled for the baseline instruction set.
#if defined(__GNUC__)
#pragma GCC diagnostic ignored "-Wpsabi"  // so3_fast.h's 4-lane helpers are never out of line
#endif

#include "imuconv/kernels/preintegration.h"
#include "so3_fast.h"

namespace imuconv::kernels {

Mat3 JrInvTimesVecDerivative(const Vec3& theta, const Vec3& omega) {
  const double t2 = theta.squaredNorm(), t = std::sqrt(t2);
  const detail::TangentCoefs k = detail::ComputeTangentCoefs(t, t2);
  return detail::JrInvTimesVecDerivative(theta, omega, k.d, k.e);
}

// Exp(phi) dR Exp(omega dt + dt domega) = Exp(phi + dR Exp(omega dt) Jr(omega dt) dt domega) dR'
// to first order, and Exp(w) Jr(w) = Jl(w).
void ManifoldStep(const Vec3& acc, const Vec3& omega, double dt, ManifoldIncrement& s,
                  StepJacobians& J) {
  const double h = 0.5 * dt * dt;
  const Vec3 phi = omega * dt;
  const double t2 = phi.squaredNorm(), t = std::sqrt(t2);
  const detail::ExpJrCoefs k = detail::ComputeExpJrCoefs(t, t2);
  const Mat3 S = so3::skew(phi), S2 = S * S;
  const Mat3 E = Mat3::Identity() + k.a * S + k.b * S2;
  const Mat3 Jl = Mat3::Identity() + k.b * S + k.c * S2;
  const Vec3 a_start = s.dR * acc;  // acceleration in the start frame

  J.dt = dt;
  J.A_tt.setIdentity();
  J.K = (-dt) * so3::skew(a_start);
  J.N = s.dR;
  J.C_t = dt * (s.dR * Jl);

  s.dp += dt * s.dv + h * a_start;
  s.dv += dt * a_start;
  s.dR = s.dR * E;
  s.dt += dt;
}

void TangentStep(const Vec3& acc, const Vec3& omega, double dt, TangentIncrement& s,
                 StepJacobians& J) {
  const double h = 0.5 * dt * dt;
  const Vec3 theta = s.xi.segment<3>(0);
  const double t2 = theta.squaredNorm(), t = std::sqrt(t2);
  const detail::TangentCoefs k = detail::ComputeTangentCoefs(t, t2);
  const Mat3 S = so3::skew(theta), S2 = S * S;
  const Mat3 R = Mat3::Identity() + k.a * S + k.b * S2;
  const Mat3 Jl = Mat3::Identity() + k.b * S + k.c * S2;
  const Mat3 JrInv = Mat3::Identity() + 0.5 * S + k.d * S2;
  const Vec3 a_start = R * acc;

  J.dt = dt;
  J.A_tt = Mat3::Identity() + dt * detail::JrInvTimesVecDerivative(theta, omega, k.d, k.e);
  J.K = (-dt) * so3::skew(a_start) * Jl;
  J.N = R;
  J.C_t = dt * JrInv;

  s.xi.segment<3>(3) += dt * s.xi.segment<3>(6) + h * a_start;
  s.xi.segment<3>(6) += dt * a_start;
  s.xi.segment<3>(0) += dt * (JrInv * omega);
  s.dt += dt;
}

// Discrete noise: kernels::NoiseVariances (common.h) holds the densities squared; white
// noise is divided by dt per step, the bias random walks multiplied by dt. GTSAM's
// integrationCovariance and biasAccOmegaInit are zero here.

}  // namespace imuconv::kernels
