// The mean-only path (core/include/imuconv/kernels/mean_only.h, what imuconv montecarlo's
// trials run) against the full path a method's preintegration takes (its plugin, through the
// bridge's Preintegrate): the same increment bit for bit, for every method it serves.
//
// Bit for bit for every method, no tolerance: each is one kernel compiled once in imuconv_core,
// which the plugin and the mean-only path both call. euler and midpoint run the preintegration
// kernel's recursion (held input), manifold and tangent the same recursion with its covariance
// switched off; rk4's state-only mode is the same compiled function as the plugin's full run,
// whose state is the same IEEE operations in every output mode (core/src/kernels/rk4_window.h,
// "Instances"). Until rk4 was compiled in the core, its plugin and montecarlo each compiled
// their own copy of the header-only kernel, and this test had to allow them 1e-13 apart.
// The inputs are the reference cases' samples as they are, at a bias estimate, and with the
// kind of noise montecarlo adds (so the SIMD recursion sees unrounded, irregular values), over
// the whole case and a short window.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>

#include "imuconv/bridge.h"
#include "imuconv/kernels/mean_only.h"
#include "integrator_cases.h"

namespace imuconv::test {
namespace {

using kernels::MeanKernel;

struct Served {
  const char* id;
  PluginKind kind;
  MeanKernel kernel;
};

constexpr Served kServed[] = {
    {"euler", PluginKind::Propagator, MeanKernel::kEuler},
    {"midpoint", PluginKind::Propagator, MeanKernel::kMidpoint},
    {"rk4", PluginKind::Propagator, MeanKernel::kRk4},
    {"manifold", PluginKind::Preintegrator, MeanKernel::kManifold},
    {"tangent", PluginKind::Preintegrator, MeanKernel::kTangent},
};

// Bitwise equality of two matrices (EXPECT_EQ on Eigen compares values, which would let
// -0 == +0 through; that difference is harmless but is not "the same arithmetic", so the
// bytes are compared, then the values are printed on failure).
template <class A>
bool SameBits(const Eigen::MatrixBase<A>& a, const Eigen::MatrixBase<A>& b) {
  return std::memcmp(a.derived().data(), b.derived().data(), sizeof(double) * a.size()) == 0;
}

bool SameIncrement(const PreintIncrement& a, const PreintIncrement& b) {
  return SameBits(a.dR, b.dR) && SameBits(a.dp, b.dp) && SameBits(a.dv, b.dv);
}

// Largest entry difference relative to the block's size (dR's entries are O(1)).
double RelativeDifference(const PreintIncrement& a, const PreintIncrement& b) {
  return std::max({(a.dR - b.dR).cwiseAbs().maxCoeff(),
                   (a.dp - b.dp).norm() / std::max(a.dp.norm(), 1e-300),
                   (a.dv - b.dv).norm() / std::max(a.dv.norm(), 1e-300)});
}

std::vector<ImuSample> Noisy(std::vector<ImuSample> s) {
  for (ImuSample& z : s) {
    z.gyro += RandVec(3e-3);
    z.accel += RandVec(3e-2);
  }
  return s;
}

TEST(MeanOnly, SameIncrementAsTheFullPathBitForBit) {
  const Registry& reg = Plugins();
  const Vec3 bg(2e-3, -1e-3, 4e-4), ba(0.03, -0.02, 0.01);
  int compared = 0;
  for (const Served& m : kServed) {
    const PreintegrationMethod method = ResolvePreintegrationMethod(reg, m.kind, m.id);
    for (const char* name : {"smooth-0", "aggressive-0", "jitter-0", "static-0"}) {
      const ImuCase c = LoadCase(name);
      for (const auto& samples : {c.samples, Noisy(c.samples)}) {
        for (double length : {1e9, 0.5}) {  // the whole case, and its first half second
          const double t_e = std::min(samples.back().t, samples.front().t + length);
          SampleWindow w;
          ASSERT_TRUE(MakeWindow(samples.data(), samples.size(), samples.front().t, t_e, w).ok());
          const Preintegrated full = Preintegrate(reg, method, w, bg, ba, c.noise);
          PreintIncrement mean;
          const Status st = kernels::IncrementMean(m.kernel, w, bg, ba, c.noise, mean);
          ASSERT_TRUE(st.ok()) << st.message();
          const std::string what = std::string(m.id) + " on " + name;
          EXPECT_TRUE(SameIncrement(full.delta, mean))
              << what << " (largest relative difference " << RelativeDifference(full.delta, mean)
              << ")\nfull dR\n"
              << full.delta.dR << "\nmean dR\n"
              << mean.dR << "\ndp " << full.delta.dp.transpose() << " vs " << mean.dp.transpose();
          EXPECT_EQ(mean.dbg, Vec3::Zero());
          EXPECT_EQ(mean.dba, Vec3::Zero());
          ++compared;
        }
      }
    }
  }
  EXPECT_EQ(compared, 5 * 4 * 2 * 2);
}

// Bad input is refused with the full path's message, not integrated.
TEST(MeanOnly, RefusesWhatTheFullPathRefuses) {
  const ImuCase c = LoadCase("smooth-0");
  std::vector<ImuSample> s(c.samples.begin(), c.samples.begin() + 10);
  s[4].gyro.x() = std::nan("");
  SampleWindow w;
  ASSERT_TRUE(MakeWindow(s.data(), s.size(), s.front().t, s.back().t, w).ok());
  for (const Served& m : kServed) {
    PreintIncrement mean;
    const Status st =
        kernels::IncrementMean(m.kernel, w, Vec3::Zero(), Vec3::Zero(), c.noise, mean);
    EXPECT_FALSE(st.ok()) << m.id;
    EXPECT_NE(st.message().find("not finite"), std::string::npos) << m.id << ": " << st.message();
  }
}

}  // namespace
}  // namespace imuconv::test
