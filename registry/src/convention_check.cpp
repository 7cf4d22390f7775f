#include "convention_check.h"

#include <algorithm>
#include <random>
#include <sstream>
#include <tuple>
#include <vector>

#include "imuconv/numeric.h"
#include "imuconv/reference_charts.h"
#include "imuconv/so3.h"
#include "numeric_jacobian.h"

namespace imuconv::detail {
namespace {

// Gate for a plugin's analytic Jacobian against Ridders' differences: far above the
// ~1e-10 the differences reach on these smooth charts, far below any real mistake (a
// wrong sign, block or transpose shows up at O(1)).
constexpr double kJacobianCheckTol = 1e-7;
// Gate for local(x, retract(x, d)) = d: a chart that is a true inverse reaches ~1e-15.
constexpr double kRoundTripTol = 1e-9;

std::string FormatMax(double v) {
  std::ostringstream o;
  o.precision(3);
  o << v;
  return o.str();
}

// The five parts of a value, rotation first: R, p, v, bg, ba of a state; dR, dp, dv, dbg, dba
// of an increment.
auto PartsOf(ImuState& x) { return std::tie(x.R, x.p, x.v, x.bg, x.ba); }
auto PartsOf(PreintIncrement& x) { return std::tie(x.dR, x.dp, x.dv, x.dbg, x.dba); }

// Where the load-time checks evaluate a chart: the identity, a tiny value (each part given) and
// a random one (each part's scale given, drawn in the parts' order from a fixed seed).
struct CheckPointSpec {
  Vec3 tiny_rotation, tiny_p, tiny_v, tiny_bg, tiny_ba;
  unsigned seed;
  double rotation, p, v, bg, ba;
};

template <class Value>
std::vector<Value> CheckPointsFrom(const CheckPointSpec& spec) {
  std::vector<Value> xs(3);
  PartsOf(xs[1]) = std::make_tuple(so3::Exp(spec.tiny_rotation), spec.tiny_p, spec.tiny_v,
                                   spec.tiny_bg, spec.tiny_ba);
  std::mt19937 rng(spec.seed);
  std::normal_distribution<double> n(0.0, 1.0);
  auto rv = [&](double s) { return Vec3(s * n(rng), s * n(rng), s * n(rng)); };
  auto [R, p, v, bg, ba] = PartsOf(xs[2]);
  // One statement per part: the draws keep the parts' order.
  R = so3::Exp(rv(spec.rotation));
  p = rv(spec.p);
  v = rv(spec.v);
  bg = rv(spec.bg);
  ba = rv(spec.ba);
  return xs;
}

template <class Value>
std::vector<Value> CheckPoints();

template <>
std::vector<ImuState> CheckPoints<ImuState>() {
  return CheckPointsFrom<ImuState>(
      {/* tiny R, p, v, bg, ba */ Vec3(1e-7, -2e-7, 3e-7), Vec3(1e-6, 2e-6, -1e-6),
       Vec3(-1e-6, 1e-6, 2e-6), Vec3(1e-7, 0, -1e-7), Vec3(0, 1e-6, 1e-6),
       /* seed */ 12345, /* random scales R, p, v, bg, ba */ 1.0, 10.0, 2.0, 0.01, 0.1});
}

template <>
std::vector<PreintIncrement> CheckPoints<PreintIncrement>() {
  return CheckPointsFrom<PreintIncrement>(
      {/* tiny dR, dp, dv, dbg, dba */ Vec3(1e-7, -2e-7, 3e-7), Vec3(1e-6, 2e-6, -1e-6),
       Vec3(-1e-6, 1e-6, 2e-6), Vec3::Zero(), Vec3::Zero(),
       /* seed */ 54321, /* random scales dR, dp, dv, dbg, dba */ 0.7, 10.0, 3.0, 1e-3, 1e-2});
}

std::vector<Vec15> CheckDeltas() {
  std::mt19937 rng(777);
  std::normal_distribution<double> n(0.0, 1.0);
  std::vector<Vec15> ds;
  ds.push_back(Vec15::Zero());
  for (double s : {1e-6, 1e-2, 0.3}) {
    Vec15 d;
    for (int i = 0; i < 15; ++i) d[i] = s * n(rng);
    ds.push_back(d);
  }
  return ds;
}

std::string OrderProblem(const BlockOrder& order) {
  if (order.is_permutation()) return {};
  std::string got;
  for (Block b : order.blocks) {
    const char* name = BlockName(b);
    got += (got.empty() ? "" : ", ") +
           (name ? std::string(name) : "block #" + std::to_string(static_cast<int>(b)));
  }
  return "block order must be a permutation of p, theta, v, bg, ba (got " + got + ")";
}

// "" when the analytic J agrees with the numeric Jn, else by how much it differs.
std::string JacobianProblem(const Mat15& J, const Mat15& Jn, const char* name, std::size_t k) {
  const double err = (J - Jn).cwiseAbs().maxCoeff();
  if (err <= kJacobianCheckTol * std::max(1.0, Jn.cwiseAbs().maxCoeff())) return {};
  return std::string("analytic ") + name + " differs from numerical differences by " +
         FormatMax(err) + " at check state " + std::to_string(k);
}

}  // namespace

template <class Value>
std::string CheckConvention(const Chart<Value>& c, bool* analytic) {
  if (std::string e = OrderProblem(c.order()); !e.empty()) return e;
  const ReferenceChart<Value> ref;
  const auto xs = CheckPoints<Value>();
  const auto ds = CheckDeltas();
  *analytic = false;
  for (std::size_t k = 0; k < xs.size(); ++k) {
    const Value& x = xs[k];
    for (const Vec15& d : ds) {
      Value y;
      Vec15 back;
      c.retract(x, d, y);
      c.local(x, y, back);
      const double err = (back - d).cwiseAbs().maxCoeff();
      if (!(err <= kRoundTripTol * (1.0 + d.cwiseAbs().maxCoeff())))
        return "local(x, retract(x, d)) differs from d by " + FormatMax(err) + " at check state " +
               std::to_string(k) + " (|d| = " + FormatMax(d.cwiseAbs().maxCoeff()) + ")";
    }
    Mat15 J_ref_this, J_this_ref;
    const bool has_to = c.J_ref_this(x, J_ref_this);
    const bool has_from = c.J_this_ref(x, J_this_ref);
    if (has_to) {
      if (std::string e = JacobianProblem(J_ref_this, NumericJacobian(c, ref, x), "J_ref_this", k);
          !e.empty())
        return e;
      *analytic = true;
    }
    if (has_from)
      if (std::string e = JacobianProblem(J_this_ref, NumericJacobian(ref, c, x), "J_this_ref", k);
          !e.empty())
        return e;
  }
  return {};
}

template std::string CheckConvention<ImuState>(const Chart<ImuState>&, bool*);
template std::string CheckConvention<PreintIncrement>(const Chart<PreintIncrement>&, bool*);

}  // namespace imuconv::detail
