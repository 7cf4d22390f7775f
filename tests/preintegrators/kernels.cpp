// The GTSAM preintegration kernels (imuconv/kernels/preintegration.h) step by step:
//   - d/dtheta [Jr^{-1}(theta) omega] against Ridders' differences, across the series /
//     closed-form switch and beyond pi (the tangent scheme's theta is not wrapped);
//   - the coefficient series against so3.h and against the closed forms at the switch;
//   - each step's A, B, C against Ridders' differences of the step itself, in the chart the
//     kernel propagates in (start-frame rotation error for manifold, also mapped to GTSAM's
//     NavState chart; additive on [theta, p, v] for tangent);
//   - every compiled instance (baseline, AVX2, AVX-512, as the CPU allows) of the block
//     recursion against the dense 15x15 recursion F Sigma F^T + G Q G^T built from those
//     step Jacobians, including tangent angles past the series switch and past pi;
//   - no heap allocation anywhere in an interval integration, in every instance.
//
// Heap detection: Eigen's EIGEN_RUNTIME_NO_MALLOC hook reports through eigen_assert (which
// is compiled out under NDEBUG, so it is redefined to count here), and global operator new
// is counted for everything else.
#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <new>
#include <tuple>
#include <vector>

// The counting operator new below is malloc-backed, so free() in operator delete is the
// matching release; GCC cannot see that through the replaced operators.
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"

namespace {
std::atomic<long> g_eigen_heap_violations{0};
std::atomic<long> g_operator_new_calls{0};
inline void CountEigenAssert(bool ok) {
  if (!ok) ++g_eigen_heap_violations;
}
}  // namespace

#define EIGEN_RUNTIME_NO_MALLOC
#define eigen_assert(x) CountEigenAssert(static_cast<bool>(x))

void* operator new(std::size_t n) {
  ++g_operator_new_calls;
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }

#include <gtest/gtest.h>

// The coefficient functions under test are internal to the kernel; their 4-lane helpers are
// always inlined, so GCC's ABI note on 32-byte vector returns does not apply.
#pragma GCC diagnostic ignored "-Wpsabi"
#include "../../core/src/kernels/so3_fast.h"
#include "imuconv/kernels/preintegration.h"
#include "imuconv/numeric.h"
#include "imuconv_test.h"
#include "reference_cases.h"

namespace {

using namespace imuconv;
using namespace imuconv::test;
namespace k = imuconv::kernels;

// Ridders' extrapolation reaches ~1e-12 relative on these smooth maps; 1e-9 leaves three
// digits for its own error while any missing or wrong term shows at O(dt) or larger.
constexpr double kRiddersTol = 1e-9;

TEST(Kernels, JrInvTimesVecDerivativeMatchesRidders) {
  const Vec3 axis = Vec3(0.3, -0.5, 0.8).normalized();
  const Vec3 off_axis = Vec3(-0.7, 0.2, 0.4).normalized();
  const Vec3 omega(0.9, -1.7, 0.6);
  double worst = 0.0;
  for (double a : {0.0, 1e-9, 1e-4, 0.1, 0.4999999, 0.5, 0.5000001, 1.0, 2.0, 3.0, 4.0, 5.0}) {
    for (const Vec3& dir : {axis, off_axis}) {
      const Vec3 theta = a * dir;
      const Mat15 J = RiddersJacobian(
          [&](const Vec15& d, Vec15& out) {
            out.setZero();
            out.head<3>() = so3::JrInv(theta + d.head<3>()) * omega;
          },
          0.01);
      const Mat3 D = k::JrInvTimesVecDerivative(theta, omega);
      worst = std::max(worst, RelErr(D, J.topLeftCorner<3, 3>()));
      EXPECT_LT(RelErr(D, J.topLeftCorner<3, 3>()), kRiddersTol) << "|theta| = " << a << "\n"
                                                                 << D << "\n"
                                                                 << J.topLeftCorner<3, 3>();
    }
  }
  std::printf("[ worst   ] d(Jr^-1 w)/dtheta vs Ridders: %.2e\n", worst);
}

TEST(Kernels, TangentSeriesMeetTheClosedFormsAtTheSwitch) {
  // Power series just below kTangentSeriesBelow, closed forms at it: the same functions,
  // so they agree to the closed forms' own accuracy (e loses ~40 ulps to cancellation
  // there, ~1e-14 relative).
  const double t = k::detail::kTangentSeriesBelow, below = std::nextafter(t, 0.0);
  const auto series = k::detail::ComputeTangentCoefs(below, below * below);
  const auto closed = k::detail::ComputeTangentCoefs(t, t * t);
  const auto closed_below = k::detail::TangentClosed(below, below * below);
  for (const auto& [name, s, c] :
       {std::tuple{"a", series.a, closed.a}, std::tuple{"b", series.b, closed.b},
        std::tuple{"c", series.c, closed.c}, std::tuple{"d", series.d, closed.d},
        std::tuple{"e", series.e, closed.e}})
    EXPECT_LT(std::abs(s - c) / std::abs(c), 1e-12) << name << ": " << s << " vs " << c;
  EXPECT_LT(std::abs(series.e - closed_below.e) / closed_below.e, 1e-12);
}

TEST(Kernels, CombinedCoefficientsMatchSo3) {
  // The kernels evaluate Exp, Jr and Jr^{-1} from one sin/cos of the half angle or from
  // power series in t^2; so3.h evaluates each separately. Same functions, so they agree to
  // a few ulps.
  const Vec3 axis = Vec3(0.3, -0.5, 0.8).normalized();
  for (double a : {0.0, 1e-9, 0.05, 0.0999, 0.1, 0.3, 1.0, 1.9999, 2.0, 3.0, 4.5}) {
    const Vec3 phi = a * axis;
    const double t2 = phi.squaredNorm(), t = std::sqrt(t2);
    const auto c = k::detail::ComputeTangentCoefs(t, t2);
    const Mat3 S = so3::skew(phi), S2 = S * S;
    // 1e-14: a handful of ulps of unit-sized entries (Jr^{-1} at 4.5 rad has entries ~10).
    EXPECT_LT(RelErr(Mat3(Mat3::Identity() + c.a * S + c.b * S2), so3::Exp(phi)), 1e-14) << a;
    EXPECT_LT(RelErr(Mat3(Mat3::Identity() - c.b * S + c.c * S2), so3::Jr(phi)), 1e-14) << a;
    EXPECT_LT(RelErr(Mat3(Mat3::Identity() + 0.5 * S + c.d * S2), so3::JrInv(phi)), 1e-14) << a;
    const auto m = k::detail::ComputeExpJrCoefs(t, t2);  // the manifold scheme's
    EXPECT_LT(RelErr(Mat3(Mat3::Identity() + m.a * S + m.b * S2), so3::Exp(phi)), 1e-14) << a;
    EXPECT_LT(RelErr(Mat3(Mat3::Identity() - m.b * S + m.c * S2), so3::Jr(phi)), 1e-14) << a;
  }
  // The local sin/cos against libm over the range the kernels use, and past it.
  double worst = 0.0;
  for (double x = 0.0; x < 40.0; x += 0.00731) {
    double s = 0.0, c = 0.0;
    k::detail::SinCosNonNegative(x, s, c);
    worst = std::max({worst, std::abs(s - std::sin(x)), std::abs(c - std::cos(x))});
  }
  EXPECT_LT(worst, 4e-16);
  std::printf("[ worst   ] local sin/cos vs libm on [0, 40): %.2e\n", worst);
}

// One step's Jacobians against differences of the step. Input d = [dx (9), dacc, domega].
struct StepCase {
  double dt;
  Vec3 acc, omega;
};

std::vector<StepCase> StepCases() {
  return {{0.005, Vec3(1.2, -0.4, 9.7), Vec3(0.3, -0.2, 0.5)},
          {0.2, Vec3(-3.0, 5.0, 12.0), Vec3(2.0, -4.0, 3.0)},
          {0.01, Vec3(0.0, 0.0, 9.81), Vec3(0.0, 0.0, 0.0)}};
}

double g_worst_step = 0.0;

void ExpectStepJacobians(const k::StepJacobians& J, const Mat15& num, const std::string& what) {
  g_worst_step = std::max({g_worst_step, RelErr(J.A(), Mat9(num.topLeftCorner<9, 9>())),
                           RelErr(J.B(), k::Mat93(num.block<9, 3>(0, 9))),
                           RelErr(J.C(), k::Mat93(num.block<9, 3>(0, 12)))});
  EXPECT_LT(RelErr(J.A(), Mat9(num.topLeftCorner<9, 9>())), kRiddersTol)
      << what << " A\n"
      << J.A() << "\n"
      << num.topLeftCorner<9, 9>();
  EXPECT_LT(RelErr(J.B(), k::Mat93(num.block<9, 3>(0, 9))), kRiddersTol) << what << " B";
  EXPECT_LT(RelErr(J.C(), k::Mat93(num.block<9, 3>(0, 12))), kRiddersTol) << what << " C";
}

TEST(Kernels, ManifoldStepJacobiansMatchRidders) {
  Rng().seed(17);
  for (const StepCase& sc : StepCases()) {
    k::ManifoldIncrement x;
    x.dR = so3::Exp(RandVec(1.0));
    x.dp = RandVec(20.0);
    x.dv = RandVec(5.0);
    k::ManifoldIncrement x1 = x;
    k::StepJacobians J;
    k::ManifoldStep(sc.acc, sc.omega, sc.dt, x1, J);
    // The step from x with rotation dR, the given dp, dv offsets and d's input offsets.
    const auto step = [&](const Mat3& dR, const Vec15& d, const Vec3& dp, const Vec3& dv) {
      k::ManifoldIncrement y = x;
      y.dR = dR;
      y.dp = x.dp + dp;
      y.dv = x.dv + dv;
      k::StepJacobians unused;
      k::ManifoldStep(sc.acc + d.segment<3>(9), sc.omega + d.segment<3>(12), sc.dt, y, unused);
      return y;
    };
    // The kernel's own chart: Exp(phi) dR (rotation error in the start frame), dp + ddp,
    // dv + ddv.
    const Mat15 num = RiddersJacobian(
        [&](const Vec15& d, Vec15& out) {
          const k::ManifoldIncrement y =
              step(so3::Exp(d.segment<3>(0)) * x.dR, d, d.segment<3>(3), d.segment<3>(6));
          out.setZero();
          out.segment<3>(0) = so3::Log(y.dR * x1.dR.transpose());
          out.segment<3>(3) = y.dp - x1.dp;
          out.segment<3>(6) = y.dv - x1.dv;
        },
        0.01);
    ExpectStepJacobians(J, num, "manifold dt=" + std::to_string(sc.dt));

    // GTSAM's NavState chart (dR Exp(dth), dp + dR ddp, dv + dR ddv): the same Jacobians
    // after the chart change blockdiag(dR^T, dR^T, dR^T) on both sides.
    const Mat15 num_nav = RiddersJacobian(
        [&](const Vec15& d, Vec15& out) {
          const k::ManifoldIncrement y = step(x.dR * so3::Exp(d.segment<3>(0)), d,
                                              x.dR * d.segment<3>(3), x.dR * d.segment<3>(6));
          out.setZero();
          out.segment<3>(0) = so3::Log(x1.dR.transpose() * y.dR);
          out.segment<3>(3) = x1.dR.transpose() * (y.dp - x1.dp);
          out.segment<3>(6) = x1.dR.transpose() * (y.dv - x1.dv);
        },
        0.01);
    Mat9 T0 = Mat9::Zero(), T1 = Mat9::Zero();  // kernel chart -> NavState before / after
    for (int b = 0; b <= 6; b += 3) {
      T0.block<3, 3>(b, b) = x.dR.transpose();
      T1.block<3, 3>(b, b) = x1.dR.transpose();
    }
    const Mat9 A_nav = T1 * J.A() * T0.inverse();
    g_worst_step = std::max(g_worst_step, RelErr(A_nav, Mat9(num_nav.topLeftCorner<9, 9>())));
    EXPECT_LT(RelErr(A_nav, Mat9(num_nav.topLeftCorner<9, 9>())), kRiddersTol) << "NavState A";
    EXPECT_LT(RelErr(k::Mat93(T1 * J.B()), k::Mat93(num_nav.block<9, 3>(0, 9))), kRiddersTol)
        << "NavState B";
    EXPECT_LT(RelErr(k::Mat93(T1 * J.C()), k::Mat93(num_nav.block<9, 3>(0, 12))), kRiddersTol)
        << "NavState C";
  }
  std::printf("[ worst   ] manifold step A,B,C vs Ridders (so far): %.2e\n", g_worst_step);
}

TEST(Kernels, TangentStepJacobiansMatchRidders) {
  Rng().seed(18);
  for (const StepCase& sc : StepCases()) {
    for (double angle : {0.0, 0.3, 2.5, 4.0}) {
      k::TangentIncrement x;
      x.xi.segment<3>(0) = angle * Vec3(0.6, -0.3, 0.74).normalized();
      x.xi.segment<3>(3) = RandVec(20.0);
      x.xi.segment<3>(6) = RandVec(5.0);
      k::TangentIncrement x1 = x;
      k::StepJacobians J;
      k::TangentStep(sc.acc, sc.omega, sc.dt, x1, J);
      const Mat15 num = RiddersJacobian(
          [&](const Vec15& d, Vec15& out) {
            k::TangentIncrement y = x;
            y.xi += d.head<9>();
            k::StepJacobians unused;
            k::TangentStep(sc.acc + d.segment<3>(9), sc.omega + d.segment<3>(12), sc.dt, y, unused);
            out.setZero();
            out.head<9>() = y.xi - x1.xi;
          },
          0.01);
      ExpectStepJacobians(
          J, num, "tangent dt=" + std::to_string(sc.dt) + " |theta|=" + std::to_string(angle));
    }
  }
  std::printf("[ worst   ] step A,B,C vs Ridders (both schemes): %.2e\n", g_worst_step);
}

// ---- The block recursion against the dense one -----------------------------------------

/// Sigma' = F Sigma F^T + G Q G^T and H' = A H - [B C] with dense 15x15 / 9x6 matrices from
/// the reference steps' Jacobians: F = [A Fb; 0 I], Fb = [B C] (the bias error is minus
/// the random walk, so Fb has the sign of d x'/d input), Q = diag(s_a^2/dt, s_g^2/dt) on
/// the inputs and dt q^2 on the bias rows.
struct DenseResult {
  Mat15 cov = Mat15::Zero();
  Mat96 H = Mat96::Zero();
};

template <typename StepFn>
DenseResult DenseRecursion(const PreintegrationInput& in, StepFn step) {
  DenseResult r;
  const ImuNoise& n = in.noise;
  const SampleWindow& w = in.window;
  for (std::size_t j = 0; j + 1 < w.size(); ++j) {
    const ImuSample& s = w[j];
    const double dt = w[j + 1].t - s.t;
    k::StepJacobians J;
    step(Vec3(s.accel - in.ba), Vec3(s.gyro - in.bg), dt, J);
    Mat96 G;
    G << J.B(), J.C();
    Mat15 F = Mat15::Identity();
    F.topLeftCorner<9, 9>() = J.A();
    F.block<9, 6>(0, 9) = G;
    Eigen::Matrix<double, 6, 6> Qin = Eigen::Matrix<double, 6, 6>::Zero();
    Qin.diagonal() << Vec3::Constant(n.accel_noise_density * n.accel_noise_density / dt),
        Vec3::Constant(n.gyro_noise_density * n.gyro_noise_density / dt);
    Mat15 Q = Mat15::Zero();
    Q.topLeftCorner<9, 9>() = G * Qin * G.transpose();
    Q.block<3, 3>(9, 9).diagonal().setConstant(dt * n.accel_random_walk * n.accel_random_walk);
    Q.block<3, 3>(12, 12).diagonal().setConstant(dt * n.gyro_random_walk * n.gyro_random_walk);
    r.cov = F * r.cov * F.transpose() + Q;
    r.H = J.A() * r.H - G;
  }
  return r;
}

/// A case whose tangent angle passes the series switch (2 rad) and pi: 4 s spinning at
/// ~1.2 rad/s, at 200 Hz with jittered stamps.
std::vector<ImuSample> SpinningSamples() {
  std::vector<ImuSample> v;
  double t = 3.0;
  for (int kk = 0; kk <= 800; ++kk) {
    ImuSample s;
    s.t = t;
    s.gyro =
        Vec3(0.9, -0.6, 0.5) + 0.05 * Vec3(std::sin(1.1 * t), std::cos(0.7 * t), std::sin(2.3 * t));
    s.accel = Vec3(0.4 * std::cos(t), 9.81 + 0.3 * std::sin(1.7 * t), -0.8 * std::sin(0.4 * t));
    v.push_back(s);
    t += 0.005 * (1.0 + 0.1 * std::sin(17.0 * kk));
  }
  return v;
}

using k::IsaName;  // the library's names ("baseline", "avx2", "avx512")

/// max |a - b| / max|b|: relative to the matrix's own scale (covariances are ~1e-8..1e-1).
template <typename A, typename B>
double ScaledErr(const Eigen::MatrixBase<A>& a, const Eigen::MatrixBase<B>& b) {
  return (a - b).cwiseAbs().maxCoeff() / b.cwiseAbs().maxCoeff();
}

// Both sides evaluate the same first-order recursion in different operation orders (and
// charts, for manifold, converted once at the end), so they agree to accumulated rounding:
// ~1e-13 relative over 800-2000 steps; 1e-11 leaves margin while a wrong or missing term
// of any block shows at 1e-4 or larger.
constexpr double kDenseTol = 1e-11;

/// Each compiled instance is its own test, skipped (not passed) where the CPU lacks it.
class KernelInstance : public ::testing::TestWithParam<k::Isa> {
 protected:
  void SetUp() override {
    if (!k::IsaAvailable(GetParam()))
      GTEST_SKIP() << IsaName(GetParam()) << " instance: not supported by this CPU";
  }
};

INSTANTIATE_TEST_SUITE_P(Instances, KernelInstance,
                         ::testing::Values(k::Isa::kBaseline, k::Isa::kAvx2, k::Isa::kAvx512),
                         [](const ::testing::TestParamInfo<k::Isa>& i) {
                           return std::string(IsaName(i.param));
                         });

TEST_P(KernelInstance, MatchesTheDenseRecursion) {
  const k::Isa isa = GetParam();
  struct Case {
    std::string name;
    std::vector<ImuSample> samples;
    PreintegrationInput input;
  };
  std::vector<Case> cases;
  for (const char* id : {"aggressive-0", "white-0"}) {
    const ReferenceCase rc = LoadReferenceCase(id);
    cases.push_back({id, rc.samples, rc.Input()});
  }
  cases.push_back({"spinning", SpinningSamples(), LoadReferenceCase("smooth-0").Input()});
  double worst = 0.0;
  for (Case& c : cases) {
    c.input.window = WindowOver(c.samples);
    const PreintegrationInput& in = c.input;
    // Manifold: the dense recursion in the kernel's start-frame chart, then to NavState.
    k::ManifoldIncrement mx;
    const DenseResult md =
        DenseRecursion(in, [&](const Vec3& a, const Vec3& w, double dt, k::StepJacobians& J) {
          k::ManifoldStep(a, w, dt, mx, J);
        });
    Mat15 T = Mat15::Identity();
    for (int b = 0; b <= 6; b += 3) T.block<3, 3>(b, b) = mx.dR.transpose();
    const Mat15 m_cov = T * md.cov * T.transpose();
    Mat96 m_H = md.H;
    m_H.topRows<3>() = mx.dR.transpose() * m_H.topRows<3>();
    // Tangent: its own chart.
    k::TangentIncrement tx;
    const DenseResult td =
        DenseRecursion(in, [&](const Vec3& a, const Vec3& w, double dt, k::StepJacobians& J) {
          k::TangentStep(a, w, dt, tx, J);
        });
    if (c.name == "spinning") {
      EXPECT_GT(tx.xi.head<3>().norm(), M_PI) << "the case must pass pi";
    }
    {
      SCOPED_TRACE(c.name + " " + IsaName(isa));
      Preintegrated mo, to;
      k::ManifoldIncrement mi;
      k::TangentIncrement ti;
      ASSERT_TRUE(k::IntegrateManifold(in, mo, &mi, isa).ok());
      ASSERT_TRUE(k::IntegrateTangent(in, to, &ti, isa).ok());
      const double e[] = {ScaledErr(mo.cov, m_cov),  RelErr(mo.J_bias, m_H),
                          ScaledErr(to.cov, td.cov), RelErr(to.J_bias, td.H),
                          RelErr(mi.dR, mx.dR),      RelErr(ti.xi, tx.xi)};
      const char* what[] = {"manifold cov",   "manifold J_bias", "tangent cov",
                            "tangent J_bias", "manifold dR",     "tangent xi"};
      for (int i = 0; i < 6; ++i) {
        EXPECT_LT(e[i], kDenseTol) << what[i];
        worst = std::max(worst, e[i]);
      }
    }
  }
  std::printf("[ worst   ] block recursion vs dense 15x15, %s instance: %.2e\n", IsaName(isa),
              worst);
}

TEST_P(KernelInstance, IntervalIntegrationDoesNotTouchTheHeap) {
  const k::Isa isa = GetParam();
  const ReferenceCase rc = LoadReferenceCase("aggressive-0");
  const PreintegrationInput in = rc.Input();
  Preintegrated out;
  Eigen::internal::set_is_malloc_allowed(false);
  const long eigen0 = g_eigen_heap_violations.load(), new0 = g_operator_new_calls.load();
  Status s1 = k::IntegrateManifold(in, out), s2 = k::IntegrateTangent(in, out);
  if (s1.ok()) s1 = k::IntegrateManifold<true>(in, out, nullptr, isa);
  if (s2.ok()) s2 = k::IntegrateTangent<true>(in, out, nullptr, isa);
  if (s1.ok()) s1 = k::IntegrateManifold<false>(in, out, nullptr, isa);
  if (s2.ok()) s2 = k::IntegrateTangent<false>(in, out, nullptr, isa);
  const long eigen1 = g_eigen_heap_violations.load(), new1 = g_operator_new_calls.load();
  Eigen::internal::set_is_malloc_allowed(true);
  EXPECT_TRUE(s1.ok() && s2.ok());
  EXPECT_EQ(eigen1 - eigen0, 0) << "Eigen heap allocations (or failed Eigen assertions)";
  EXPECT_EQ(new1 - new0, 0) << "operator new calls";
  // The detector itself works: a dynamic-size Eigen object is caught.
  Eigen::internal::set_is_malloc_allowed(false);
  {
    Eigen::MatrixXd m(3, 3);
    m.setZero();
  }
  Eigen::internal::set_is_malloc_allowed(true);
  EXPECT_GT(g_eigen_heap_violations.load(), eigen1);
}

TEST(Kernels, AnInstanceTheCpuLacksIsRefusedNotRun) {
  // Running an AVX-512 instance on a CPU without it would crash (illegal instruction);
  // the entry points return an error instead.
  const k::Isa missing = !k::IsaAvailable(k::Isa::kAvx512) ? k::Isa::kAvx512
                         : !k::IsaAvailable(k::Isa::kAvx2) ? k::Isa::kAvx2
                                                           : k::Isa::kAuto;
  if (missing == k::Isa::kAuto) GTEST_SKIP() << "this CPU runs every instance";
  const ReferenceCase rc = LoadReferenceCase("white-0");
  const PreintegrationInput in = rc.Input();
  Preintegrated out;
  const Status m = k::IntegrateManifold(in, out, nullptr, missing),
               t = k::IntegrateTangent(in, out, nullptr, missing);
  ASSERT_FALSE(m.ok());
  ASSERT_FALSE(t.ok());
  EXPECT_NE(m.message().find("does not run on this CPU"), std::string::npos) << m.message();
  k::StartFrameManifold sf;
  EXPECT_FALSE(k::IntegrateManifoldStartFrame(in, k::Hold::Euler, true, missing, sf).ok());
}

}  // namespace
