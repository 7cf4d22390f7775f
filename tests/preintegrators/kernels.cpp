// The GTSAM preintegration kernels (imuconv/kernels/gtsam_preintegration.h) step by step:
//   - d/dtheta [Jr^{-1}(theta) omega] against Ridders' differences, across the series /
//     closed-form switch and beyond pi (the tangent scheme's theta is not wrapped);
//   - each step's A, B, C against Ridders' differences of the step itself, in the scheme's
//     own chart (NavState chart for manifold, additive on [theta, p, v] for tangent);
//   - no heap allocation anywhere in an interval integration.
//
// Heap detection: Eigen's EIGEN_RUNTIME_NO_MALLOC hook reports through eigen_assert (which
// is compiled out under NDEBUG, so it is redefined to count here), and global operator new
// is counted for everything else.
#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <new>

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

#include "imuconv/kernels/gtsam_preintegration.h"
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
      EXPECT_LT(RelErr(D, J.topLeftCorner<3, 3>()), kRiddersTol) << "|theta| = " << a << "\n" << D << "\n"
                                                                   << J.topLeftCorner<3, 3>();
    }
  }
  std::printf("[ worst   ] d(Jr^-1 w)/dtheta vs Ridders: %.2e\n", worst);
}

TEST(Kernels, DPrimeOverTIsContinuousAtTheSeriesSwitch) {
  // Both branches at t = 0.5 (series just below, closed form at): they must agree to the
  // closed form's own accuracy, ~30/t^2 ulps relative = 3e-14.
  const double t = k::detail::kDPrimeSeriesBelow, below = std::nextafter(t, 0.0);
  const double series = k::detail::ComputeTangentCoefs(below, below * below).e;
  const double closed = k::detail::ComputeTangentCoefs(t, t * t).e;
  EXPECT_LT(std::abs(series - closed) / closed, 1e-12) << series << " vs " << closed;
}

TEST(Kernels, CombinedCoefficientsMatchSo3) {
  // The kernels evaluate Exp, Jr and Jr^{-1} from one sin/cos of the half angle; so3.h
  // evaluates each separately. Same functions, so they agree to a few ulps.
  const Vec3 axis = Vec3(0.3, -0.5, 0.8).normalized();
  for (double a : {0.0, 1e-9, 0.05, 0.0999, 0.1, 0.3, 1.0, 3.0, 4.5}) {
    const Vec3 phi = a * axis;
    const double t2 = phi.squaredNorm(), t = std::sqrt(t2);
    const auto c = k::detail::ComputeTangentCoefs(t, t2);
    const Mat3 S = so3::skew(phi), S2 = S * S;
    // 1e-14: a handful of ulps of unit-sized entries (Jr^{-1} at 4.5 rad has entries ~10).
    EXPECT_LT(RelErr(Mat3(Mat3::Identity() + c.a * S + c.b * S2), so3::Exp(phi)), 1e-14) << a;
    EXPECT_LT(RelErr(Mat3(Mat3::Identity() - c.b * S + c.c * S2), so3::Jr(phi)), 1e-14) << a;
    EXPECT_LT(RelErr(Mat3(Mat3::Identity() + 0.5 * S + c.d * S2), so3::JrInv(phi)), 1e-14) << a;
    const auto m = k::detail::ComputeExpJrCoefs(t, t2);
    EXPECT_EQ(m.a, c.a);
    EXPECT_EQ(m.b, c.b);
    EXPECT_EQ(m.c, c.c);
  }
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
  EXPECT_LT(RelErr(J.A(), Mat9(num.topLeftCorner<9, 9>())), kRiddersTol) << what << " A\n"
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
    // The step from x perturbed by d's rotation part and the given dp, dv offsets.
    const auto step = [&](const Vec15& d, const Vec3& dp, const Vec3& dv) {
      k::ManifoldIncrement y = x;
      y.dR = x.dR * so3::Exp(d.segment<3>(0));
      y.dp = x.dp + dp;
      y.dv = x.dv + dv;
      k::StepJacobians unused;
      k::ManifoldStep(sc.acc + d.segment<3>(9), sc.omega + d.segment<3>(12), sc.dt, y, unused);
      return y;
    };
    // The kernel's own chart: dR Exp(dth), dp + ddp, dv + ddv.
    const Mat15 num = RiddersJacobian(
        [&](const Vec15& d, Vec15& out) {
          const k::ManifoldIncrement y = step(d, d.segment<3>(3), d.segment<3>(6));
          out.setZero();
          out.segment<3>(0) = so3::Log(x1.dR.transpose() * y.dR);
          out.segment<3>(3) = y.dp - x1.dp;
          out.segment<3>(6) = y.dv - x1.dv;
        },
        0.01);
    ExpectStepJacobians(J, num, "manifold dt=" + std::to_string(sc.dt));

    // GTSAM's NavState chart (dR Exp(dth), dp + dR ddp, dv + dR ddv): the same Jacobians
    // after the chart change blockdiag(I, dR^T, dR^T) on both sides.
    const Mat15 num_nav = RiddersJacobian(
        [&](const Vec15& d, Vec15& out) {
          const k::ManifoldIncrement y = step(d, x.dR * d.segment<3>(3), x.dR * d.segment<3>(6));
          out.setZero();
          out.segment<3>(0) = so3::Log(x1.dR.transpose() * y.dR);
          out.segment<3>(3) = x1.dR.transpose() * (y.dp - x1.dp);
          out.segment<3>(6) = x1.dR.transpose() * (y.dv - x1.dv);
        },
        0.01);
    Mat9 T0 = Mat9::Identity(), T1 = Mat9::Identity();  // ref -> NavState before / after
    for (int b = 3; b <= 6; b += 3) {
      T0.block<3, 3>(b, b) = x.dR.transpose();
      T1.block<3, 3>(b, b) = x1.dR.transpose();
    }
    const Mat9 A_nav = T1 * J.A() * T0.inverse();
    g_worst_step = std::max(g_worst_step, RelErr(A_nav, Mat9(num_nav.topLeftCorner<9, 9>())));
    EXPECT_LT(RelErr(A_nav, Mat9(num_nav.topLeftCorner<9, 9>())), kRiddersTol) << "NavState A";
    EXPECT_LT(RelErr(k::Mat93(T1 * J.B()), k::Mat93(num_nav.block<9, 3>(0, 9))), kRiddersTol) << "NavState B";
    EXPECT_LT(RelErr(k::Mat93(T1 * J.C()), k::Mat93(num_nav.block<9, 3>(0, 12))), kRiddersTol) << "NavState C";
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
      ExpectStepJacobians(J, num, "tangent dt=" + std::to_string(sc.dt) + " |theta|=" + std::to_string(angle));
    }
  }
  std::printf("[ worst   ] step A,B,C vs Ridders (both schemes): %.2e\n", g_worst_step);
}

TEST(Kernels, IntervalIntegrationDoesNotTouchTheHeap) {
  const ReferenceCase rc = LoadReferenceCase("aggressive-0");
  const PreintegrationInput in = rc.Input();
  NativePreintegration out;
  Eigen::internal::set_is_malloc_allowed(false);
  const long eigen0 = g_eigen_heap_violations.load(), new0 = g_operator_new_calls.load();
  const Status s1 = k::IntegrateManifold(in, out);
  const Status s2 = k::IntegrateTangent(in, out);
  const long eigen1 = g_eigen_heap_violations.load(), new1 = g_operator_new_calls.load();
  Eigen::internal::set_is_malloc_allowed(true);
  EXPECT_TRUE(s1.ok() && s2.ok());
  EXPECT_EQ(eigen1 - eigen0, 0) << "Eigen heap allocations (or failed Eigen assertions)";
  EXPECT_EQ(new1 - new0, 0) << "operator new calls";
  // The detector itself works: a dynamic-size Eigen object is caught.
  Eigen::internal::set_is_malloc_allowed(false);
  { Eigen::MatrixXd m(3, 3); m.setZero(); }
  Eigen::internal::set_is_malloc_allowed(true);
  EXPECT_GT(g_eigen_heap_violations.load(), eigen1);
}

}  // namespace
