// The preintegration kernel of GTSAM's two schemes, with the covariance of
// PreintegratedCombinedMeasurements and the first-order bias Jacobians (J. Huai, "IMU
// Propagation as Preintegration", "GTSAM Peculiarities"):
//
//   manifold: the increment (dR, dp, dv) is a NavState updated on the manifold
//             (GTSAM's ManifoldPreintegration);
//   tangent:  the increment is the 9-vector xi = [theta, p, v] with dR = Exp(theta),
//             integrated in the tangent space at the identity (GTSAM's
//             TangentPreintegration).
//
// Both hold knot j of the window over [t_j, t_j+1] (the discrete form of the paper's eq.
// preint-theta..preint-v). This header is the kernel's public face: the step
// specification in plain Eigen (what the compiled recursion implements, and what the tests
// difference) and the entry points. The recursion itself, compiled once per instruction
// set and chosen at run time from the CPU, lives in the library (core/src/kernels/).
#pragma once

#include "imuconv/enum_name.h"
#include "imuconv/export.h"
#include "imuconv/preintegrator.h"
#include "imuconv/status.h"
#include "imuconv/types.h"

namespace imuconv::kernels {

using Mat93 = Eigen::Matrix<double, 9, 3>;

/// Jacobians of one step in GTSAM's notation, in the kernel's chart:
///   A = d x'/d x = [A_tt 0 0; K dt/2  I  I dt; K  0  I],
///   B = d x'/d acc = [0; N dt^2/2; N dt],  C = d x'/d omega = [C_t; 0; 0].
struct StepJacobians {
  double dt = 0.0;
  Mat3 A_tt;  ///< d theta' / d theta
  Mat3 K;     ///< d v' / d theta (and 2/dt d p' / d theta)
  Mat3 N;     ///< rotation of the accelerometer input into the start frame
  Mat3 C_t;   ///< d theta' / d omega

  Mat9 A() const {
    Mat9 a = Mat9::Identity();
    a.block<3, 3>(0, 0) = A_tt;
    a.block<3, 3>(3, 0) = (0.5 * dt) * K;
    a.block<3, 3>(3, 6).diagonal().setConstant(dt);
    a.block<3, 3>(6, 0) = K;
    return a;
  }
  Mat93 B() const {
    Mat93 b = Mat93::Zero();
    b.block<3, 3>(3, 0) = (0.5 * dt * dt) * N;
    b.block<3, 3>(6, 0) = dt * N;
    return b;
  }
  Mat93 C() const {
    Mat93 c = Mat93::Zero();
    c.block<3, 3>(0, 0) = C_t;
    return c;
  }
};

/// Increment of the manifold scheme.
struct ManifoldIncrement {
  double dt = 0.0;
  Mat3 dR = Mat3::Identity();
  Vec3 dp = Vec3::Zero(), dv = Vec3::Zero();
};

/// Increment of the tangent scheme: xi = [theta, p, v] with dR = Exp(theta).
struct TangentIncrement {
  double dt = 0.0;
  Vec9 xi = Vec9::Zero();
};

/// One zero-order-hold step of the manifold scheme with bias-corrected inputs
/// acc = a_m - ba_hat, omega = w_m - bg_hat held over dt:
///   dp' = dp + dv dt + dR acc dt^2/2,  dv' = dv + dR acc dt,  dR' = dR Exp(omega dt).
/// Jacobians in the start-frame chart (Exp(phi) dR, dp + ddp, dv + ddv), dR before the step:
///   A_tt = I,  K = -dt [dR acc]x,  N = dR,  C_t = dR Jl(omega dt) dt.
IMUCONV_API void ManifoldStep(const Vec3& acc, const Vec3& omega, double dt, ManifoldIncrement& s,
                              StepJacobians& J);

/// One zero-order-hold step of the tangent scheme, with R = Exp(theta):
///   theta' = theta + Jr^{-1}(theta) omega dt,  p' = p + v dt + R acc dt^2/2,  v' = v + R acc dt.
/// Exact Jacobians in the additive chart of xi:
///   A_tt = I + d(Jr^{-1}(theta) omega)/dtheta dt,  K = -[R acc]x Jl(theta) dt,
///   N = R,  C_t = Jr^{-1}(theta) dt.
IMUCONV_API void TangentStep(const Vec3& acc, const Vec3& omega, double dt, TangentIncrement& s,
                             StepJacobians& J);

/// d/dtheta [Jr^{-1}(theta) omega] for fixed omega: the exact derivative of the tangent
/// scheme's angular-rate map.
IMUCONV_API Mat3 JrInvTimesVecDerivative(const Vec3& theta, const Vec3& omega);

/// Which compiled instance of the kernels (this one's recursion, and rk4's, kernels/rk4.h) to
/// run: kAuto picks the widest one the CPU supports (decided once); the others exist so tests
/// and benchmarks can run each one. kBaseline is the target's 128-bit vector instance (x86-64:
/// SSE2; aarch64: NEON), or the portable path on a compiler without GCC/Clang vector
/// extensions. kPortable is the portable path on every build (this kernel: Eigen 3x3 blocks,
/// core/src/kernels/portable.cpp; rk4: its default-target code): what a compiler without vector
/// extensions runs, and the oracle the tests compare the instances with. kAuto never picks it.
enum class Isa { kAuto, kBaseline, kAvx2, kAvx512, kPortable };

/// Whether `isa` was compiled into this build and can run on this CPU (kAuto always can).
IMUCONV_API bool IsaAvailable(Isa isa);
/// The widest instance this CPU runs (never kAuto), decided once.
IMUCONV_API Isa BestIsa();
/// "auto", "baseline", "avx2", "avx512", "portable" (benchmark names; the shard files of run and
/// montecarlo, which record BestIsa(), never "portable").
inline const char* IsaName(Isa isa) {
  static constexpr const char* kNames[] = {"auto", "baseline", "avx2", "avx512",
                                           "portable"};  // from kAuto on
  return EnumName(isa, Isa::kAuto, kNames, "auto");
}

/// Checks what the drivers rely on: at least two knots, finite data, strictly increasing
/// time, finite bias estimate, non-negative finite noise. Allocates only to report an error.
IMUCONV_API Status CheckPreintegrationInput(const PreintegrationInput& in);

/// Manifold scheme over the window; covariance in the NavState chart ("gtsam_manifold"),
/// bias Jacobian in dR Exp(dtheta), additive dp, dv ("gtsam_manifold_jacobian"). Without
/// `covariance`, out.cov is zero (for re-integrations that need the mean only). An `isa`
/// this CPU lacks is an error, never run.
IMUCONV_API Status IntegrateManifold(const PreintegrationInput& in, Preintegrated& out,
                                     ManifoldIncrement* increment, Isa isa, bool covariance);
/// Tangent scheme over the window; covariance and bias Jacobian additive on the tangent
/// 9-vector ("gtsam_tangent"). Otherwise as IntegrateManifold.
IMUCONV_API Status IntegrateTangent(const PreintegrationInput& in, Preintegrated& out,
                                    TangentIncrement* increment, Isa isa, bool covariance);

template <bool kCovariance = true>
inline Status IntegrateManifold(const PreintegrationInput& in, Preintegrated& out,
                                ManifoldIncrement* increment = nullptr, Isa isa = Isa::kAuto) {
  return IntegrateManifold(in, out, increment, isa, kCovariance);
}
template <bool kCovariance = true>
inline Status IntegrateTangent(const PreintegrationInput& in, Preintegrated& out,
                               TangentIncrement* increment = nullptr, Isa isa = Isa::kAuto) {
  return IntegrateTangent(in, out, increment, isa, kCovariance);
}

// ---- For the held-input propagators (kernels/euler.h), whose step is the manifold step.

/// How the value held over [t_k, t_k+1] is formed from the knots.
enum class Hold {
  Euler,     ///< knot k (GTSAM's input)
  Midpoint,  ///< mean of knots k and k+1 (OpenVINS' imu_avg; GTSAM's reference "mid")
};

/// The manifold recursion's result in its own start-frame chart (Exp(phi) dR, dp + e_p,
/// dv + e_v; bias error delta b = -Delta b), before any change of chart.
struct StartFrameManifold {
  ManifoldIncrement increment;
  Mat96 J_inc_bias;  ///< d [theta, p, v] / d (ba, bg)
  Mat15 cov;         ///< [theta, p, v, ba, bg]; left untouched without covariance
};

/// The manifold scheme with the given hold, without the input checks (the caller has made
/// them). Its only error: an `isa` this CPU lacks (kBaseline runs the baseline instance of
/// the SIMD recursion where the compiler has one, else the portable path).
IMUCONV_API Status IntegrateManifoldStartFrame(const PreintegrationInput& in, Hold hold,
                                               bool covariance, Isa isa, StartFrameManifold& out);

}  // namespace imuconv::kernels
