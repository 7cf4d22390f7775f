// Whether a built-in scheme gives the mean alone (increment_mean(), core/include/imuconv/
// increment_mean.h; what imuconv montecarlo's trials run), declared in each system's own test
// file (declared_facts.h), one line per plugin id:
//   IMUCONV_INCREMENT_MEAN(Propagator, euler, kProvided);
// (or with its noise, IMUCONV_SCHEME_FACTS, scheme_fact_declarations.h)
// in tests/integrators/ for a propagator, tests/preintegrators/ for a preintegrator; and what
// the declaration promises, checked by CheckDeclaredIncrementMeans (run by each area's
// mean_only.cpp), which also fails for a plugin of the kind loaded from the built-in directory
// without a declaration:
//  - kProvided: the increment is the full path's (its plugin through the bridge's Preintegrate)
//    bit for bit, no tolerance: the mean and the full path are one kernel compiled once in
//    imuconv_core, called by both (tests/integrators/mean_only.cpp says why for each of the
//    core's schemes); and bad input is refused with the full path's message;
//  - kNotProvided: it says so (IsIncrementMeanNotProvided, the base classes' default, which
//    montecarlo answers with the full path) and writes the identity rather than leave `delta`
//    as it was.
// The inputs are the reference cases' samples as they are, at a bias estimate, and with the
// kind of noise montecarlo adds (so a SIMD recursion sees unrounded, irregular values), over
// the whole case and a short window.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "declared_facts.h"
#include "imuconv/bridge.h"
#include "imuconv/increment_mean.h"
#include "imuconv/preintegrator.h"
#include "imuconv/window.h"
#include "imuconv_test.h"
#include "reference_case.h"
#include "scheme_facts.h"

namespace imuconv::test {

enum class IncrementMeanGiven { kProvided, kNotProvided };
template <PluginKind kKind>
struct IncrementMeanOf {
  using Facts = IncrementMeanGiven;
  static constexpr const char* kWhat = "increment_mean() (kProvided or kNotProvided)";
};

namespace increment_mean_facts {

/// The plugin's increment_mean(), as montecarlo calls it.
template <PluginKind kKind>
Status PluginMean(const std::string& id, const SampleWindow& w, const Vec3& bg, const Vec3& ba,
                  const ImuNoise& noise, PreintIncrement& mean) {
  return SchemePlugin<kKind>(id)->increment_mean(PreintegrationInputOf(w, bg, ba, noise), mean);
}

/// Bitwise equality of two matrices (EXPECT_EQ on Eigen compares values, which would let
/// -0 == +0 through; that difference is harmless but is not "the same arithmetic", so the
/// bytes are compared, then the values are printed on failure).
template <class A>
bool SameBits(const Eigen::MatrixBase<A>& a, const Eigen::MatrixBase<A>& b) {
  return std::memcmp(a.derived().data(), b.derived().data(), sizeof(double) * a.size()) == 0;
}
inline bool SameIncrement(const PreintIncrement& a, const PreintIncrement& b) {
  return SameBits(a.dR, b.dR) && SameBits(a.dp, b.dp) && SameBits(a.dv, b.dv);
}
/// Largest entry difference relative to the block's size (dR's entries are O(1)).
inline double RelativeDifference(const PreintIncrement& a, const PreintIncrement& b) {
  return std::max({(a.dR - b.dR).cwiseAbs().maxCoeff(),
                   (a.dp - b.dp).norm() / std::max(a.dp.norm(), 1e-300),
                   (a.dv - b.dv).norm() / std::max(a.dv.norm(), 1e-300)});
}
inline std::vector<ImuSample> Noisy(std::vector<ImuSample> s) {
  for (ImuSample& z : s) {
    z.gyro += RandVec(3e-3);
    z.accel += RandVec(3e-2);
  }
  return s;
}

/// The mean against the full path, bit for bit, on four cases, their samples as they are and
/// noisy, over the whole case and its first half second: 16 comparisons.
template <PluginKind kKind>
void ExpectSameAsTheFullPath(const std::string& id) {
  const Registry& reg = Plugins();
  const Vec3 bg(2e-3, -1e-3, 4e-4), ba(0.03, -0.02, 0.01);
  const PreintegrationMethod method = ResolvePreintegrationMethod(reg, kKind, id);
  int compared = 0;
  for (const char* name : {"smooth-0", "aggressive-0", "jitter-0", "static-0"}) {
    const nlohmann::json c = CaseJson(name);
    const ImuNoise noise = CaseNoise(c);
    const std::vector<ImuSample> as_they_are = CaseSamples(c);
    for (const auto& samples : {as_they_are, Noisy(as_they_are)}) {
      for (double length : {1e9, 0.5}) {  // the whole case, and its first half second
        const double t_e = std::min(samples.back().t, samples.front().t + length);
        SampleWindow w;
        ASSERT_TRUE(MakeWindow(samples.data(), samples.size(), samples.front().t, t_e, w).ok());
        const Preintegrated full = Preintegrate(reg, method, w, bg, ba, noise);
        PreintIncrement mean;
        const Status st = PluginMean<kKind>(id, w, bg, ba, noise, mean);
        ASSERT_TRUE(st.ok()) << id << ": " << st.message();
        const std::string what = id + " on " + name;
        EXPECT_TRUE(SameIncrement(full.delta, mean))
            << what << " (largest relative difference " << RelativeDifference(full.delta, mean)
            << ")\nfull dR\n"
            << full.delta.dR << "\nmean dR\n"
            << mean.dR << "\ndp " << full.delta.dp.transpose() << " vs " << mean.dp.transpose();
        EXPECT_EQ(mean.dbg, Vec3::Zero()) << what;
        EXPECT_EQ(mean.dba, Vec3::Zero()) << what;
        ++compared;
      }
    }
  }
  EXPECT_EQ(compared, 4 * 2 * 2) << id;
}

/// Bad input (a sample not finite) is refused with the full path's message, not integrated.
template <PluginKind kKind>
void ExpectRefusesWhatTheFullPathRefuses(const std::string& id) {
  const nlohmann::json c = CaseJson("smooth-0");
  const std::vector<ImuSample> all = CaseSamples(c);
  std::vector<ImuSample> s(all.begin(), all.begin() + 10);
  s[4].gyro.x() = std::nan("");
  SampleWindow w;
  ASSERT_TRUE(MakeWindow(s.data(), s.size(), s.front().t, s.back().t, w).ok());
  PreintIncrement mean;
  const Status st = PluginMean<kKind>(id, w, Vec3::Zero(), Vec3::Zero(), CaseNoise(c), mean);
  EXPECT_FALSE(st.ok()) << id;
  EXPECT_NE(st.message().find("not finite"), std::string::npos) << id << ": " << st.message();
}

/// "Not provided", and the identity written over a stale `delta`.
template <PluginKind kKind>
void ExpectSaysNotProvided(const std::string& id) {
  const nlohmann::json c = CaseJson("smooth-0");
  const std::vector<ImuSample> s = CaseSamples(c);
  SampleWindow w;
  ASSERT_TRUE(MakeWindow(s.data(), 20, s.front().t, s[19].t, w).ok());
  PreintIncrement mean;
  mean.dp = Vec3(1.0, 2.0, 3.0);
  const Status st = PluginMean<kKind>(id, w, Vec3::Zero(), Vec3::Zero(), CaseNoise(c), mean);
  EXPECT_TRUE(IsIncrementMeanNotProvided(st)) << id << ": " << st.message();
  EXPECT_EQ(mean.dp, Vec3::Zero()) << id;
}

}  // namespace increment_mean_facts

/// Every declaration of the kind holds (above), and every plugin of the kind loaded from the
/// built-in plugin directory has one (`where` says in which files they belong).
template <PluginKind kKind>
void CheckDeclaredIncrementMeans(const char* where) {
  CheckSchemeDeclarations<IncrementMeanOf, kKind>(
      where, "IMUCONV_INCREMENT_MEAN", "kProvided or kNotProvided",
      [](const std::string& id, IncrementMeanGiven given) {
        if (given == IncrementMeanGiven::kProvided) {
          increment_mean_facts::ExpectSameAsTheFullPath<kKind>(id);
          increment_mean_facts::ExpectRefusesWhatTheFullPathRefuses<kKind>(id);
        } else {
          increment_mean_facts::ExpectSaysNotProvided<kKind>(id);
        }
      });
}

}  // namespace imuconv::test

/// Declares whether the plugin ID of kind KIND (Propagator or Preintegrator) gives the mean
/// alone: GIVEN is kProvided or kNotProvided.
#define IMUCONV_INCREMENT_MEAN(KIND, ID, GIVEN)                                                \
  [[maybe_unused]] static const bool KIND##_##ID##_increment_mean_declared = ::imuconv::test:: \
      DeclaredFacts<::imuconv::test::IncrementMeanOf<::imuconv::PluginKind::KIND>>::Add(       \
          #ID, ::imuconv::test::IncrementMeanGiven::GIVEN, {__FILE__, __LINE__})
