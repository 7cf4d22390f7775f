// The generic test suite every perturbation convention runs, manif-style: one macro defines
// the suite for a kind of convention (states or increments), one line in each convention's
// own test file instantiates it:
//   IMUCONV_DECLARE_CONVENTION_SUITE(StateConventionSuite);           (state/suite.h)
//   IMUCONV_DEFINE_CONVENTION_SUITE(StateConventionSuite, StateKind)   (state/all.cpp)
//   IMUCONV_CONVENTION_SUITE(StateConventionSuite, gtsam_navstate);    (state/gtsam_navstate.cpp)
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
#include <vector>

#include "imuconv/numeric.h"
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
    for (const auto& [check, err] : Worst()) std::printf("[ worst    ] %-44s %.3e\n", check.c_str(), err);
  }
};

// ---- the two kinds ---------------------------------------------------------------------

struct StateKind {
  using Value = ImuState;
  using Convention = StateConvention;
  static constexpr PluginKind kKind = PluginKind::StateConvention;
  static constexpr const char* kReference = "left";

  static std::shared_ptr<const Convention> Get(const std::string& id) { return Plugins().state_convention(id); }
  static void RefRetract(const Value& x, const Vec15& d, Value& y) { LeftRetract(x, d, y); }
  static void RefLocal(const Value& x, const Value& y, Vec15& d) { LeftLocal(x, y, d); }
  static Mat15 Conversion(const std::string& a, const std::string& b, const Value& x) {
    return Plugins().conversion(a, b, x);
  }
  /// Identity, tiny, and two random states (TestStates draws fresh random ones per call).
  static const std::vector<Value>& Points() {
    static const std::vector<Value> xs = [] {
      std::vector<Value> v = TestStates();
      v.push_back(TestStates()[2]);
      return v;
    }();
    return xs;
  }
  /// Max |a - b| over all entries of two values.
  static double Distance(const Value& a, const Value& b) {
    return std::max({(a.R - b.R).cwiseAbs().maxCoeff(), (a.p - b.p).cwiseAbs().maxCoeff(),
                     (a.v - b.v).cwiseAbs().maxCoeff(), (a.bg - b.bg).cwiseAbs().maxCoeff(),
                     (a.ba - b.ba).cwiseAbs().maxCoeff()});
  }
};

struct IncrementKind {
  using Value = PreintIncrement;
  using Convention = IncrementConvention;
  static constexpr PluginKind kKind = PluginKind::IncrementConvention;
  static constexpr const char* kReference = "preint_reference";

  static std::shared_ptr<const Convention> Get(const std::string& id) { return Plugins().increment_convention(id); }
  static void RefRetract(const Value& x, const Vec15& d, Value& y) { PreintReferenceRetract(x, d, y); }
  static void RefLocal(const Value& x, const Value& y, Vec15& d) { PreintReferenceLocal(x, y, d); }
  static Mat15 Conversion(const std::string& a, const std::string& b, const Value& x) {
    return Plugins().increment_conversion(a, b, x);
  }
  static const std::vector<Value>& Points() {
    static const std::vector<Value> xs = [] {
      std::vector<Value> v = TestIncrements();
      v.push_back(TestIncrements()[2]);
      return v;
    }();
    return xs;
  }
  static double Distance(const Value& a, const Value& b) {
    return std::max({(a.dR - b.dR).cwiseAbs().maxCoeff(), (a.dp - b.dp).cwiseAbs().maxCoeff(),
                     (a.dv - b.dv).cwiseAbs().maxCoeff(), (a.dbg - b.dbg).cwiseAbs().maxCoeff(),
                     (a.dba - b.dba).cwiseAbs().maxCoeff()});
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
Map15 ChartMap(const typename K::Convention& a, const typename K::Convention& b, const typename K::Value& x) {
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
      EXPECT_LE(err, kRoundTripTol) << id << " at point " << k << ", |d| = " << d.cwiseAbs().maxCoeff();
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
    EXPECT_LE(eto, tol) << id << " J_ref_this at point " << k << "\nanalytic\n" << Jto << "\n" << how
                        << "\n" << Nto;
    EXPECT_LE(efrom, tol) << id << " J_this_ref at point " << k << "\nanalytic\n" << Jfrom << "\n"
                          << how << "\n" << Nfrom;
  }
}

template <typename K>
void CheckJacobiansInverse(const std::string& id) {
  const auto c = K::Get(id);
  for (const auto& x : K::Points()) {
    Mat15 Jto, Jfrom;
    ASSERT_TRUE(c->J_ref_this(x, Jto));
    ASSERT_TRUE(c->J_this_ref(x, Jfrom));
    const double e = std::max(RelErr(Jto * Jfrom, Mat15::Identity()), RelErr(Jfrom * Jto, Mat15::Identity()));
    Record("J_to_ref J_from_ref - I", e);
    EXPECT_LE(e, kInverseTol) << id;
  }
}

/// Every ordered pair (A, B) of loaded conventions of the kind, A = B included.
template <typename K>
void CheckAllPairs() {
  const std::vector<std::string> ids = Plugins().ids(K::kKind);
  ASSERT_GE(ids.size(), 2u);
  const auto& xs = K::Points();
  for (const auto& a : ids)
    for (const auto& b : ids) {
      const auto ca = K::Get(a), cb = K::Get(b);
      for (std::size_t k = 0; k < xs.size(); ++k) {
        SCOPED_TRACE(a + " -> " + b + " at point " + std::to_string(k));
        const auto& x = xs[k];
        const Mat15 Jab = K::Conversion(a, b, x), Jba = K::Conversion(b, a, x);
        const double einv = RelErr(Jab * Jba, Mat15::Identity());
        Record("pair J_AB J_BA - I", einv);
        EXPECT_LE(einv, kPairInverseTol);
        // Directly through the two plugins' charts, not through the registry.
        const Map15 f = ChartMap<K>(*ca, *cb, x);
        const double ec = RelErr(Jab, CentralJacobian(f, kCentralStep));
        Record("pair J_AB vs central h=1e-6", ec);
        EXPECT_LE(ec, kCentralTol);
        const double er = RelErr(Jab, RiddersJacobian(f));
        Record("pair J_AB vs Ridders", er);
        EXPECT_LE(er, kRiddersTol);
      }
    }
}

/// The registry's fallback for a plugin without analytic Jacobians is Ridders' differences of
/// each factor, J_{B<-ref} J_{ref<-A}; composing those numerical factors must reproduce the
/// analytic conversion (and so would a registry that had to fall back).
template <typename K>
void CheckNumericalComposition() {
  const std::vector<std::string> ids = Plugins().ids(K::kKind);
  const auto& xs = K::Points();
  for (const auto& a : ids)
    for (const auto& b : ids) {
      const auto ca = K::Get(a), cb = K::Get(b);
      for (std::size_t k = 0; k < xs.size(); ++k) {
        SCOPED_TRACE(a + " -> " + b + " at point " + std::to_string(k));
        const auto& x = xs[k];
        const Mat15 numeric = RiddersJacobian(FromReferenceMap<K>(*cb, x)) * RiddersJacobian(ToReferenceMap<K>(*ca, x));
        const double e = RelErr(numeric, K::Conversion(a, b, x));
        Record("Ridders-composed vs registry conversion", e);
        EXPECT_LE(e, kRiddersTol);
      }
    }
}

/// Every loaded convention of the kind has an instantiation of the suite named
/// "<id>/<suite>" (so a new plugin without its one line is noticed).
template <typename K>
void CheckEveryConventionHasSuite(const std::string& suite) {
  std::set<std::string> instantiated;
  const auto* ut = ::testing::UnitTest::GetInstance();
  for (int i = 0; i < ut->total_test_suite_count(); ++i) instantiated.insert(ut->GetTestSuite(i)->name());
  for (const auto& id : Plugins().ids(K::kKind))
    EXPECT_TRUE(instantiated.count(id + "/" + suite)) << "convention '" << id << "' has no IMUCONV_CONVENTION_SUITE("
                                                      << suite << ", " << id << ") line";
}

/// Writes M into the (row_label, col_label) block of J, where rows are in convention `to`'s
/// order and columns in `from`'s: a hand-built expected conversion reads like its derivation.
class BlockBuilder {
 public:
  BlockBuilder(const BlockLabels& to, const BlockLabels& from) : to_(to), from_(from) { J_.setZero(); }
  BlockBuilder& set(const char* row_label, const char* col_label, const Mat3& M) {
    J_.block<3, 3>(BlockOffset(to_, row_label), BlockOffset(from_, col_label)) = M;
    return *this;
  }
  const Mat15& matrix() const { return J_; }

 private:
  BlockLabels to_, from_;
  Mat15 J_;
};

}  // namespace imuconv::test

/// Declares the suite class SUITE (in a header every convention's test file includes).
#define IMUCONV_DECLARE_CONVENTION_SUITE(SUITE) \
  class SUITE : public ::testing::TestWithParam<std::string> {}

/// Defines the full per-convention suite SUITE for a kind (StateKind or IncrementKind), once per
/// test executable.
#define IMUCONV_DEFINE_CONVENTION_SUITE(SUITE, KIND)                                                      \
  TEST_P(SUITE, LabelsAndAnalyticJacobiansRegistered) { ::imuconv::test::CheckLabels<KIND>(GetParam()); } \
  TEST_P(SUITE, RetractOfZeroIsTheEstimate) { ::imuconv::test::CheckRetractZero<KIND>(GetParam()); }      \
  TEST_P(SUITE, LocalInvertsRetract) { ::imuconv::test::CheckRoundTrip<KIND>(GetParam()); }                \
  TEST_P(SUITE, AnalyticJacobiansMatchCentralDifferences) {                                               \
    ::imuconv::test::CheckAnalyticJacobians<KIND>(GetParam(), false);                                     \
  }                                                                                                       \
  TEST_P(SUITE, AnalyticJacobiansMatchRidders) { ::imuconv::test::CheckAnalyticJacobians<KIND>(GetParam(), true); } \
  TEST_P(SUITE, ToAndFromReferenceAreInverse) { ::imuconv::test::CheckJacobiansInverse<KIND>(GetParam()); }

/// Runs the suite SUITE for the convention with id ID (an identifier-like id).
#define IMUCONV_CONVENTION_SUITE(SUITE, ID) \
  INSTANTIATE_TEST_SUITE_P(ID, SUITE, ::testing::Values(std::string(#ID)))
