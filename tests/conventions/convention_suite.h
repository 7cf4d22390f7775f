// The generic test suite every perturbation convention runs, manif-style: one macro defines
// the suite for a kind of convention (states or increments), one line in each convention's
// own test file instantiates it, with the facts the convention documents:
//   IMUCONV_DECLARE_CONVENTION_SUITE(StateConventionSuite);           (below)
//   IMUCONV_DEFINE_CONVENTION_SUITE(StateConventionSuite, StateKind)   (state/all.cpp)
//   IMUCONV_STATE_CONVENTION(gtsam_navstate, "theta p v ba bg");       (state/gtsam_navstate.cpp)
// the last being IMUCONV_CONVENTION_SUITE(StateConventionSuite, gtsam_navstate) and the block
// order it documents, IMUCONV_CONVENTION_BLOCK_ORDER (below).
//
// Everything is checked against the convention's own retract/local and the kind's reference
// chart (`left` or `preint_reference`), never against the registry's derived results, so a
// wrong plugin cannot vouch for itself. The worst error of each check is recorded and
// printed at the end of the run (imuconv::test::Worst()).
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "declared_facts.h"
#include "imuconv/numeric.h"
#include "imuconv/plugin/convention.h"
#include "imuconv/reference_charts.h"
#include "imuconv_test.h"

namespace imuconv::test {

// ---- tolerances, each with the reason it is what it is ---------------------------------

// local(x, retract(x, d)) = d, measured as max|error| / max(1, max|d|): the charts are a few
// well-conditioned products, Exp and Log of O(1) numbers, so rounding leaves ~1e-15; relative
// to |d| itself would be meaningless for d = 1e-8 because p^ + dp - p^ cancels |p^| ~ 20.
constexpr double kRoundTripTol = 1e-12;
// retract(x, 0) = x: only gtsam_tangent is not bit-exact (Exp(Log(dR)) rounds to ~1e-16).
constexpr double kRetractZeroTol = 1e-14;
// Analytic vs central differences with h = 1e-6 (RelErr): truncation h^2 |f'''| / 6 ~ 1e-13,
// rounding eps |x| / h ~ 1e-16 * 20 / 1e-6 = 2e-9 (additive blocks cancel |p^| ~ 20).
constexpr double kCentralStep = 1e-6;
constexpr double kCentralTol = 1e-8;
// Analytic vs Ridders' extrapolation (RelErr): the brief's "accurate to 1e-10 relative";
// Ridders' smallest step is ~2e-3, so rounding contributes ~1e-12 and truncation is
// extrapolated away.
constexpr double kRiddersTol = 1e-10;
// J_to_reference J_from_reference = I: products of O(1..20) blocks, rounding ~1e-14.
constexpr double kInverseTol = 1e-12;
// conversion(A, B) conversion(B, A) = I (the brief's bound): two registry products of
// analytic factors, rounding ~1e-14.
constexpr double kPairInverseTol = 1e-10;
// Hand-derived expectations of structure: the same closed forms evaluated differently
// (e.g. R^T vs the plugin's transpose, Jr vs its own product), rounding ~1e-15.
constexpr double kStructureTol = 1e-14;

/// Worst error seen per check name, printed after the run for the report.
inline std::map<std::string, double>& Worst() {
  static std::map<std::string, double> w;
  return w;
}
inline void Record(const std::string& check, double err) {
  double& w = Worst()[check];
  w = std::max(w, err);
}

class PrintWorstErrors : public ::testing::Environment {
 public:
  void TearDown() override {
    for (const auto& [check, err] : Worst())
      std::printf("[ worst    ] %-44s %.3e\n", check.c_str(), err);
  }
};

// ---- the two kinds ---------------------------------------------------------------------

/// The points a kind is tested at: Draw()'s identity, tiny and random values and one more
/// random value from a second call (Draw() makes fresh random values each time), drawn once.
template <auto Draw>
const auto& FixedPoints() {
  static const auto xs = [] {
    auto v = Draw();
    v.push_back(Draw()[2]);
    return v;
  }();
  return xs;
}
/// Max |entry| over differences of the members of two values (a kind's Distance).
template <typename... Diff>
double MaxAbs(const Diff&... diffs) {
  return std::max({static_cast<double>(diffs.cwiseAbs().maxCoeff())...});
}

/// What both kinds share: the value, its chart interface and its reference chart; the plugin
/// kind of its conventions, the registry's accessor of one (kGet, e.g.
/// &Registry::state_convention) and the points it is tested at (FixedPoints<kDraw>).
template <class V, PluginKind kConventionKind, auto kGet, auto kDraw>
struct ChartKind {
  using Value = V;
  using Convention = Chart<V>;
  static constexpr PluginKind kKind = kConventionKind;
  static auto Get(const std::string& id) { return (Plugins().*kGet)(id); }
  static const std::vector<V>& Points() { return FixedPoints<kDraw>(); }
  static constexpr const char* kReference = ReferenceChart<V>::id;
  static void RefRetract(const V& x, const Vec15& d, V& y) { ReferenceChart<V>::retract(x, d, y); }
  static void RefLocal(const V& x, const V& y, Vec15& d) { ReferenceChart<V>::local(x, y, d); }
  /// The registry's Jacobian between the conventions `a` and `b` of the kind at `x`.
  static Mat15 Conversion(const std::string& a, const std::string& b, const V& x) {
    return Plugins().conversion(a, b, x);
  }
};

struct StateKind
    : ChartKind<ImuState, PluginKind::StateConvention, &Registry::state_convention, TestStates> {
  static double Distance(const Value& a, const Value& b) {
    return MaxAbs(a.R - b.R, a.p - b.p, a.v - b.v, a.ba - b.ba, a.bg - b.bg);
  }
};

struct IncrementKind : ChartKind<PreintIncrement, PluginKind::IncrementConvention,
                                 &Registry::increment_convention, TestIncrements> {
  static double Distance(const Value& a, const Value& b) {
    return MaxAbs(a.dR - b.dR, a.dp - b.dp, a.dv - b.dv, a.dba - b.dba, a.dbg - b.dbg);
  }
};

/// Perturbations of max-norm 1e-8, 1e-3 and 0.5, three random directions each.
inline const std::vector<Vec15>& Deltas() {
  static const std::vector<Vec15> ds = [] {
    std::vector<Vec15> v;
    for (double s : {1e-8, 1e-3, 0.5})
      for (int k = 0; k < 3; ++k) {
        const Vec15 u = RandVec15(1.0);
        v.push_back(s / u.cwiseAbs().maxCoeff() * u);
      }
    return v;
  }();
  return ds;
}

// ---- Jacobians straight from the charts ------------------------------------------------

/// f(d) = local_B(x, retract_A(x, d)), the map whose derivative at 0 every conversion is.
template <typename K>
Map15 ChartMap(const typename K::Convention& a, const typename K::Convention& b,
               const typename K::Value& x) {
  return [&a, &b, &x](const Vec15& d, Vec15& out) {
    typename K::Value y;
    a.retract(x, d, y);
    b.local(x, y, out);
  };
}
/// d local_ref(x, retract_C(x, d)) and d local_C(x, retract_ref(x, e)).
template <typename K>
Map15 ToReferenceMap(const typename K::Convention& c, const typename K::Value& x) {
  return [&c, &x](const Vec15& d, Vec15& out) {
    typename K::Value y;
    c.retract(x, d, y);
    K::RefLocal(x, y, out);
  };
}
template <typename K>
Map15 FromReferenceMap(const typename K::Convention& c, const typename K::Value& x) {
  return [&c, &x](const Vec15& e, Vec15& out) {
    typename K::Value y;
    K::RefRetract(x, e, y);
    c.local(x, y, out);
  };
}

// ---- the checks ------------------------------------------------------------------------

template <typename K>
void CheckRoundTrip(const std::string& id) {
  const auto c = K::Get(id);
  const auto& xs = K::Points();
  for (std::size_t k = 0; k < xs.size(); ++k)
    for (const Vec15& d : Deltas()) {
      typename K::Value y;
      Vec15 back;
      c->retract(xs[k], d, y);
      c->local(xs[k], y, back);
      const double err = (back - d).cwiseAbs().maxCoeff() / std::max(1.0, d.cwiseAbs().maxCoeff());
      Record("round trip local(x, retract(x, d)) - d", err);
      EXPECT_LE(err, kRoundTripTol)
          << id << " at point " << k << ", |d| = " << d.cwiseAbs().maxCoeff();
    }
}

template <typename K>
void CheckRetractZero(const std::string& id) {
  const auto c = K::Get(id);
  for (const auto& x : K::Points()) {
    typename K::Value y;
    c->retract(x, Vec15::Zero(), y);
    EXPECT_LE(K::Distance(x, y), kRetractZeroTol) << id;
  }
}

template <typename K>
void CheckLabels(const std::string& id) {
  const auto c = K::Get(id);
  const BlockLabels labels = c->labels();
  std::set<std::string> got(labels.begin(), labels.end());
  EXPECT_EQ(got, (std::set<std::string>{"p", "theta", "v", "bg", "ba"})) << id;
  const PluginInfo& info = Plugins().info(K::kKind, id);
  EXPECT_EQ(info.blocks, std::vector<std::string>(labels.begin(), labels.end())) << id;
  EXPECT_TRUE(info.analytic_jacobians) << id << ": the registry fell back to numerical Jacobians";
}

template <typename K>
void CheckAnalyticJacobians(const std::string& id, bool ridders) {
  const auto c = K::Get(id);
  const auto& xs = K::Points();
  for (std::size_t k = 0; k < xs.size(); ++k) {
    const auto& x = xs[k];
    Mat15 Jto, Jfrom;
    ASSERT_TRUE(c->J_ref_this(x, Jto)) << id << " gives no analytic J_ref_this";
    ASSERT_TRUE(c->J_this_ref(x, Jfrom)) << id << " gives no analytic J_this_ref";
    const Map15 to = ToReferenceMap<K>(*c, x), from = FromReferenceMap<K>(*c, x);
    const Mat15 Nto = ridders ? RiddersJacobian(to) : CentralJacobian(to, kCentralStep);
    const Mat15 Nfrom = ridders ? RiddersJacobian(from) : CentralJacobian(from, kCentralStep);
    const double tol = ridders ? kRiddersTol : kCentralTol;
    const std::string how = ridders ? "Ridders" : "central h=1e-6";
    const double eto = RelErr(Jto, Nto), efrom = RelErr(Jfrom, Nfrom);
    Record("analytic vs " + how, std::max(eto, efrom));
    EXPECT_LE(eto, tol) << id << " J_ref_this at point " << k << "\nanalytic\n"
                        << Jto << "\n"
                        << how << "\n"
                        << Nto;
    EXPECT_LE(efrom, tol) << id << " J_this_ref at point " << k << "\nanalytic\n"
                          << Jfrom << "\n"
                          << how << "\n"
                          << Nfrom;
  }
}

template <typename K>
void CheckJacobiansInverse(const std::string& id) {
  const auto c = K::Get(id);
  for (const auto& x : K::Points()) {
    Mat15 Jto, Jfrom;
    ASSERT_TRUE(c->J_ref_this(x, Jto));
    ASSERT_TRUE(c->J_this_ref(x, Jfrom));
    const double e =
        std::max(RelErr(Jto * Jfrom, Mat15::Identity()), RelErr(Jfrom * Jto, Mat15::Identity()));
    Record("J_to_ref J_from_ref - I", e);
    EXPECT_LE(e, kInverseTol) << id;
  }
}

/// Runs `check(a, b, ca, cb, x)` for every ordered pair (a, b) of the conventions `ids` of the
/// kind, a = b included (ca, cb: their charts), at every fixed point x of the kind, with the
/// pair and the point in the trace of what it reports.
template <typename K, typename Check>
void ForEachPairAtEachPoint(const std::vector<std::string>& ids, Check check) {
  const auto& xs = K::Points();
  for (const auto& a : ids)
    for (const auto& b : ids) {
      const auto ca = K::Get(a), cb = K::Get(b);
      for (std::size_t k = 0; k < xs.size(); ++k) {
        SCOPED_TRACE(a + " -> " + b + " at point " + std::to_string(k));
        check(a, b, *ca, *cb, xs[k]);
      }
    }
}

/// Every ordered pair (A, B) of loaded conventions of the kind, A = B included.
template <typename K>
void CheckAllPairs() {
  const std::vector<std::string> ids = Plugins().ids(K::kKind);
  ASSERT_GE(ids.size(), 2u);
  ForEachPairAtEachPoint<K>(ids, [](const std::string& a, const std::string& b, const auto& ca,
                                    const auto& cb, const typename K::Value& x) {
    const Mat15 Jab = K::Conversion(a, b, x), Jba = K::Conversion(b, a, x);
    const double einv = RelErr(Jab * Jba, Mat15::Identity());
    Record("pair J_AB J_BA - I", einv);
    EXPECT_LE(einv, kPairInverseTol);
    // Directly through the two plugins' charts, not through the registry.
    const Map15 f = ChartMap<K>(ca, cb, x);
    const double ec = RelErr(Jab, CentralJacobian(f, kCentralStep));
    Record("pair J_AB vs central h=1e-6", ec);
    EXPECT_LE(ec, kCentralTol);
    const double er = RelErr(Jab, RiddersJacobian(f));
    Record("pair J_AB vs Ridders", er);
    EXPECT_LE(er, kRiddersTol);
  });
}

/// The registry's fallback for a plugin without analytic Jacobians is Ridders' differences of
/// each factor, J_{B<-ref} J_{ref<-A}; composing those numerical factors must reproduce the
/// analytic conversion (and so would a registry that had to fall back).
template <typename K>
void CheckNumericalComposition() {
  ForEachPairAtEachPoint<K>(
      Plugins().ids(K::kKind), [](const std::string& a, const std::string& b, const auto& ca,
                                  const auto& cb, const typename K::Value& x) {
        const Mat15 numeric =
            RiddersJacobian(FromReferenceMap<K>(cb, x)) * RiddersJacobian(ToReferenceMap<K>(ca, x));
        const double e = RelErr(numeric, K::Conversion(a, b, x));
        Record("Ridders-composed vs registry conversion", e);
        EXPECT_LE(e, kRiddersTol);
      });
}

/// The block order a convention's documentation states, "labels in order" (e.g. "p theta v bg
/// ba"), declared in that convention's own test file with IMUCONV_CONVENTION_BLOCK_ORDER.
template <typename K>
struct BlockOrderOf {
  using Facts = const char*;
  static constexpr const char* kWhat = "block order";
};
/// The chart an increment convention states its bias Jacobians in (jacobian_convention()),
/// declared in its own test file with IMUCONV_BIAS_JACOBIAN_CHART.
struct BiasJacobianChart {
  using Facts = const char*;
  static constexpr const char* kWhat = "bias-Jacobian chart";
};

/// Every declared block order is the loaded plugin's (its labels and the registry's record of
/// them), and every convention of the kind loaded from the built-in plugin directory has one.
template <typename K>
void CheckDeclaredBlockOrders(const char* where) {
  DeclaredFacts<BlockOrderOf<K>>::CheckAll(
      Plugins(), K::kKind, where, "IMUCONV_CONVENTION_BLOCK_ORDER(<Kind>, <id>, \"...\")",
      [](const std::string& id, const char* order) {
        std::string got;
        for (const std::string& label : Plugins().info(K::kKind, id).blocks)
          got += (got.empty() ? "" : " ") + label;
        EXPECT_EQ(got, order) << id;
      });
}

/// Every loaded convention of the kind has an instantiation of the suite named
/// "<id>/<suite>" (so a new plugin without its one line is noticed).
template <typename K>
void CheckEveryConventionHasSuite(const std::string& suite) {
  std::set<std::string> instantiated;
  const auto* ut = ::testing::UnitTest::GetInstance();
  for (int i = 0; i < ut->total_test_suite_count(); ++i)
    instantiated.insert(ut->GetTestSuite(i)->name());
  for (const auto& id : Plugins().ids(K::kKind))
    EXPECT_TRUE(instantiated.count(id + "/" + suite))
        << "convention '" << id << "' has no IMUCONV_CONVENTION_SUITE(" << suite << ", " << id
        << ") line";
}

/// One block of a conversion derived by hand: the 3x3 map from block `col` of the source
/// chart to block `row` of the target chart; {label, M} names a diagonal block.
struct BlockEntry {
  BlockEntry(const char* block, const Mat3& map) : row(block), col(block), M(map) {}
  BlockEntry(const char* row_block, const char* col_block, const Mat3& map)
      : row(row_block), col(col_block), M(map) {}
  const char* row;
  const char* col;
  Mat3 M;
};
using BlockEntries = std::vector<BlockEntry>;

/// At every test point x, the registry's conversion `from` -> `to` equals the matrix built
/// from its derivation: each block mapped to the same block of the other chart by the
/// identity, overwritten by the entries blocks(x) names, placed at the offsets of each
/// chart's own labels (so the expectation reads like the derivation, in either order).
template <typename K, typename BlocksAt>
void ExpectConversionByBlocks(const char* from, const char* to, BlocksAt blocks) {
  const BlockLabels rows = K::Get(to)->labels(), cols = K::Get(from)->labels();
  const auto block = [&](Mat15& J, const char* row, const char* col) {
    return J.block<3, 3>(BlockOffset(rows, row), BlockOffset(cols, col));
  };
  for (const auto& x : K::Points()) {
    Mat15 expected = Mat15::Zero();
    for (const char* b : rows) block(expected, b, b).setIdentity();
    for (const BlockEntry& e : blocks(x)) block(expected, e.row, e.col) = e.M;
    const Mat15 J = K::Conversion(from, to, x);
    EXPECT_LE(RelErr(J, expected), kStructureTol) << from << " -> " << to << "\ngot\n"
                                                  << J << "\nexpected\n"
                                                  << expected;
  }
}

}  // namespace imuconv::test

/// The names every convention's test file is written in.
namespace imuconv::test::conventions {
using namespace imuconv::plugin::prelude;  // the names the plugins are written in
using imuconv::test::BlockEntries;
using imuconv::test::IncrementKind;
using imuconv::test::kStructureTol;
using imuconv::test::Plugins;
using imuconv::test::RelErr;
using imuconv::test::StateKind;
inline const Mat3 I3 = Mat3::Identity();

/// The registry's conversion `from` -> `to` against the blocks derived by hand, for the kind
/// whose value blocks(x) takes (identity on every block not named; ExpectConversionByBlocks).
template <typename BlocksAt>
void ExpectConversion(const char* from, const char* to, BlocksAt blocks) {
  using Kind =
      std::conditional_t<std::is_invocable_v<BlocksAt, const ImuState&>, StateKind, IncrementKind>;
  ExpectConversionByBlocks<Kind>(from, to, blocks);
}

/// The increment convention `id` perturbs every block as preint_reference does (right rotation
/// error, plus signs throughout), in an order of its own: both conversions are permutations.
inline void ExpectReferenceReordered(const char* id) {
  const auto none = [](const PreintIncrement&) -> BlockEntries { return {}; };
  ExpectConversion(id, "preint_reference", none);
  ExpectConversion("preint_reference", id, none);
}

/// The increment convention `id` takes a left rotation error, Exp(dtheta) dR^ = dR^ Exp(dR^T
/// dtheta), and perturbs every other block as preint_reference does: the reference's rotation
/// error is dR^T times its own, and its own dR times the reference's.
inline void ExpectReferenceWithLeftRotation(const char* id) {
  ExpectConversion(id, "preint_reference", [](const PreintIncrement& x) -> BlockEntries {
    return {{"theta", x.dR.transpose()}};
  });
  ExpectConversion("preint_reference", id, [](const PreintIncrement& x) -> BlockEntries {
    return {{"theta", x.dR}};
  });
}
}  // namespace imuconv::test::conventions

/// Declares the suite class SUITE (in a header every convention's test file includes).
#define IMUCONV_DECLARE_CONVENTION_SUITE(SUITE) \
  class SUITE : public ::testing::TestWithParam<std::string> {}

/// Defines the full per-convention suite SUITE for a kind (StateKind or IncrementKind), once per
/// test executable, with the kind-wide checks: every loaded convention runs it, and every
/// ordered pair converts through the registry as the two charts say.
#define IMUCONV_DEFINE_CONVENTION_SUITE(SUITE, KIND)                                        \
  TEST_P(SUITE, LabelsAndAnalyticJacobiansRegistered) {                                     \
    ::imuconv::test::CheckLabels<KIND>(GetParam());                                         \
  }                                                                                         \
  TEST_P(SUITE, RetractOfZeroIsTheEstimate) {                                               \
    ::imuconv::test::CheckRetractZero<KIND>(GetParam());                                    \
  }                                                                                         \
  TEST_P(SUITE, LocalInvertsRetract) { ::imuconv::test::CheckRoundTrip<KIND>(GetParam()); } \
  TEST_P(SUITE, AnalyticJacobiansMatchCentralDifferences) {                                 \
    ::imuconv::test::CheckAnalyticJacobians<KIND>(GetParam(), false);                       \
  }                                                                                         \
  TEST_P(SUITE, AnalyticJacobiansMatchRidders) {                                            \
    ::imuconv::test::CheckAnalyticJacobians<KIND>(GetParam(), true);                        \
  }                                                                                         \
  TEST_P(SUITE, ToAndFromReferenceAreInverse) {                                             \
    ::imuconv::test::CheckJacobiansInverse<KIND>(GetParam());                               \
  }                                                                                         \
  TEST(SUITE##Kind, EveryLoadedConventionRunsTheSuite) {                                    \
    ::imuconv::test::CheckEveryConventionHasSuite<KIND>(#SUITE);                            \
  }                                                                                         \
  TEST(SUITE##Pairs, ConversionsInvertAndMatchTheChartsDirectly) {                          \
    ::imuconv::test::CheckAllPairs<KIND>();                                                 \
  }                                                                                         \
  TEST(SUITE##Pairs, RiddersComposedConversionMatchesAnalytic) {                            \
    ::imuconv::test::CheckNumericalComposition<KIND>();                                     \
  }                                                                                         \
  static const auto* const SUITE##PrintWorst =                                              \
      ::testing::AddGlobalTestEnvironment(new ::imuconv::test::PrintWorstErrors)

/// Declares the block order the convention ID (of KIND, StateKind or IncrementKind) documents,
/// ORDER its labels in order ("p theta v bg ba"): one line in the convention's own test file,
/// checked against the plugin by the kind's BuiltInsAndTheirBlockOrders (state/all.cpp,
/// increment/all.cpp), which also fails for a loaded convention without the line.
#define IMUCONV_CONVENTION_BLOCK_ORDER(KIND, ID, ORDER)                                          \
  [[maybe_unused]] static const bool KIND##_##ID##_block_order_declared =                        \
      ::imuconv::test::DeclaredFacts<::imuconv::test::BlockOrderOf<::imuconv::test::KIND>>::Add( \
          #ID, ORDER, {__FILE__, __LINE__})

/// Declares the chart the increment convention ID states its bias Jacobians in (CHART, an id
/// string): one line in its own test file, checked by PreintConventions.BiasJacobianCharts.
#define IMUCONV_BIAS_JACOBIAN_CHART(ID, CHART)                                 \
  [[maybe_unused]] static const bool ID##_bias_jacobian_chart_declared =       \
      ::imuconv::test::DeclaredFacts<::imuconv::test::BiasJacobianChart>::Add( \
          #ID, CHART, {__FILE__, __LINE__})

/// Runs the suite SUITE for the convention with id ID (an identifier-like id).
#define IMUCONV_CONVENTION_SUITE(SUITE, ID) \
  INSTANTIATE_TEST_SUITE_P(ID, SUITE, ::testing::Values(std::string(#ID)))

/// The state convention ID's one line in its own test file: it runs StateConventionSuite and
/// documents the block order ORDER (IMUCONV_CONVENTION_SUITE, IMUCONV_CONVENTION_BLOCK_ORDER).
#define IMUCONV_STATE_CONVENTION(ID, ORDER)           \
  IMUCONV_CONVENTION_SUITE(StateConventionSuite, ID); \
  IMUCONV_CONVENTION_BLOCK_ORDER(StateKind, ID, ORDER)

/// The increment convention ID's one line: it runs IncrementConventionSuite, documents the block
/// order ORDER and states its bias Jacobians in CHART (the three declarations above at once).
#define IMUCONV_INCREMENT_CONVENTION(ID, ORDER, CHART)      \
  IMUCONV_CONVENTION_SUITE(IncrementConventionSuite, ID);   \
  IMUCONV_CONVENTION_BLOCK_ORDER(IncrementKind, ID, ORDER); \
  IMUCONV_BIAS_JACOBIAN_CHART(ID, CHART)

// Each convention's test file includes this header, instantiates its kind's suite in one
// line and writes its hand-derived conversions in the names of imuconv::test::conventions.
IMUCONV_DECLARE_CONVENTION_SUITE(StateConventionSuite);
IMUCONV_DECLARE_CONVENTION_SUITE(IncrementConventionSuite);
using namespace imuconv::test::conventions;  // NOLINT: the vocabulary of the convention tests
