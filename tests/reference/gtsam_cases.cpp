// The ten shared reference cases against GTSAM 4.3a0 (tests/data/reference, FORMAT.md).
//
// Metric: the paper's entrywise difference d = |r - e|/|r| where |r| > 1e-4, else |r - e|.
// Tolerances (issue 3, FORMAT.md):
//   zoh.manifold (euler + preintegration by propagation + conversion) and zoh.tangent
//   (native tangent) use exactly GTSAM's discretisation: max d <= 1e-8 on every field;
//   mid_exact (the same schemes on GTSAM's averaged `mid` input): max d <= 1e-8;
//   mid.* (rk4, linear interpolation) differ from GTSAM's `mid` only by discretisation:
//   mean d <= 1e-3 for the bias Jacobian and the covariances, averaged over the smooth
//   cases as the paper's Figure 1 averages over runs. Other fields are printed: GTSAM's
//   tangent scheme integrates theta with a first-order step in the tangent space, so its own
//   deltaR differs from its manifold scheme's by ~1e-4 rad over 10 s (visible in the
//   reference files themselves), and that is the floor for every rotation-dependent field.
#include <gtest/gtest.h>

#include <cstdio>
#include <map>

#include "imuconv_test.h"
#include "refcase.h"

namespace {

using nlohmann::json;
using imuconv::test::DataPath;
using imuconv::test::EntryDiff;
using imuconv::test::Plugins;
using imuconv::test::ReadJson;

const char* kCases[] = {"aggressive-0", "aggressive-1", "jitter-0", "jitter-1", "smooth-0",
                        "smooth-1",     "smooth-2",     "smooth-3", "static-0", "white-0"};

struct Stat {
  double max = 0.0, sum = 0.0;
  std::size_t n = 0;
  double mean() const { return n ? sum / n : 0.0; }
};

// Walks the reference value and compares every number with the estimate at the same path.
void Compare(const json& ref, const json& est, const std::string& path, std::map<std::string, Stat>& out,
             const std::string& field) {
  if (ref.is_number()) {
    ASSERT_TRUE(est.is_number()) << path << " missing in imuconv's output";
    const double d = EntryDiff(ref.get<double>(), est.get<double>());
    Stat& s = out[field];
    s.max = std::max(s.max, d);
    s.sum += d;
    ++s.n;
  } else if (ref.is_array()) {
    ASSERT_TRUE(est.is_array() && est.size() == ref.size()) << path << ": shape differs";
    for (std::size_t i = 0; i < ref.size(); ++i) Compare(ref[i], est[i], path + "/" + std::to_string(i), out, field);
  } else if (ref.is_object()) {
    for (auto it = ref.begin(); it != ref.end(); ++it) {
      if (it.key() == "variant" || it.key() == "selfcheck_cov15_maxabs") continue;
      ASSERT_TRUE(est.contains(it.key())) << path << "/" << it.key() << " missing in imuconv's output";
      Compare(it.value(), est[it.key()], path + "/" + it.key(), out, field.empty() ? it.key() : field);
    }
  }
}

class GtsamCase : public ::testing::TestWithParam<const char*> {
 protected:
  static json& Output(const std::string& id) {
    static std::map<std::string, json> cache;
    auto it = cache.find(id);
    if (it == cache.end())
      it = cache.emplace(id, imuconv::refcase::Run(Plugins(), ReadJson(DataPath("reference/cases/" + id + ".json"))))
               .first;
    return it->second;
  }
  static json Reference(const std::string& id) { return ReadJson(DataPath("reference/gtsam/" + id + ".gtsam.json")); }
};

void ExpectMaxBelow(const std::map<std::string, Stat>& stats, double tol, const std::string& what) {
  for (const auto& [field, s] : stats) {
    std::printf("  %-28s %-18s max d %.3g  mean d %.3g\n", what.c_str(), field.c_str(), s.max, s.mean());
    EXPECT_LE(s.max, tol) << what << " " << field;
  }
}

TEST_P(GtsamCase, ZohSchemesMatchGtsamToRounding) {
  const std::string id = GetParam();
  const json ref = Reference(id), est = Output(id);
  for (const char* variant : {"manifold", "tangent"}) {
    std::map<std::string, Stat> stats;
    Compare(ref["zoh"][variant], est["zoh"][variant], std::string("/zoh/") + variant, stats, "");
    ExpectMaxBelow(stats, 1e-8, id + " zoh." + variant);
  }
}

TEST_P(GtsamCase, SameSchemesOnAveragedInputMatchGtsamMid) {
  const std::string id = GetParam();
  const json ref = Reference(id), est = Output(id);
  for (const char* variant : {"manifold", "tangent"}) {
    std::map<std::string, Stat> stats;
    Compare(ref["mid"][variant], est["mid_exact"][variant], std::string("/mid_exact/") + variant, stats, "");
    ExpectMaxBelow(stats, 1e-8, id + " mid_exact." + variant);
  }
}

TEST_P(GtsamCase, Rk4AgreesWithGtsamMidToDiscretisation) {
  const std::string id = GetParam();
  const json ref = Reference(id), est = Output(id);
  for (const char* variant : {"manifold", "tangent"}) {
    std::map<std::string, Stat> stats;
    Compare(ref["mid"][variant], est["mid"][variant], std::string("/mid/") + variant, stats, "");
    for (const auto& [field, s] : stats)
      std::printf("  %-28s %-18s max d %.3g  mean d %.3g\n", (id + " mid." + variant).c_str(), field.c_str(), s.max,
                  s.mean());
  }
}

TEST(GtsamMid, Rk4BiasJacobianAndCovarianceWithinPaperFigure1OnSmoothCases) {
  for (const char* variant : {"manifold", "tangent"}) {
    std::map<std::string, Stat> stats;
    for (const char* id : {"smooth-0", "smooth-1", "smooth-2", "smooth-3"}) {
      const json ref = ReadJson(DataPath(std::string("reference/gtsam/") + id + ".gtsam.json"));
      const json est = imuconv::refcase::Run(Plugins(), ReadJson(DataPath(std::string("reference/cases/") + id + ".json")));
      for (const char* f : {"J_bias", "cov15", "cov9"})
        Compare(ref["mid"][variant][f], est["mid"][variant][f], f, stats, f);
    }
    for (const auto& [field, s] : stats) {
      std::printf("  smooth mid.%-9s %-8s mean d %.3g  max d %.3g\n", variant, field.c_str(), s.mean(), s.max);
      EXPECT_LE(s.mean(), 1e-3) << variant << " " << field;
    }
  }
}

TEST_P(GtsamCase, EulerPropagationEqualsPropagationByItsPreintegration) {
  // Paper, section 3.2: the zoh.manifold measurement, propagated by preintegration from
  // cov_s_left, must give the euler integrator's own Phi and covariance. Both are exact
  // derivatives of the same discrete map, so they agree to rounding; 1e-8 in d leaves
  // room for the ~1e-12 relative error of 2000 accumulated steps.
  const std::string id = GetParam();
  const json& est = Output(id);
  std::map<std::string, Stat> stats;
  const json& a = est["propagation"]["euler"];
  const json& b = est["propagation"]["by_preintegration_zoh_manifold"];
  for (const char* f : {"Phi", "cov"}) Compare(a[f], b[f], f, stats, f);
  Compare(a["state_e"], b["state_e"], "state_e", stats, "state_e");
  ExpectMaxBelow(stats, 1e-8, id + " euler vs by-preint");
}

INSTANTIATE_TEST_SUITE_P(Reference, GtsamCase, ::testing::ValuesIn(kCases),
                         [](const auto& info) {
                           std::string s = info.param;
                           for (char& c : s)
                             if (c == '-') c = '_';
                           return s;
                         });

}  // namespace
