#include "convention_check.h"

#include <algorithm>
#include <random>
#include <sstream>
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

template <class Value>
std::vector<Value> CheckPoints();

// Sample points for the load-time checks: identity, tiny and random (fixed seed).
template <>
std::vector<ImuState> CheckPoints<ImuState>() {
  std::vector<ImuState> xs(3);
  xs[1].R = so3::Exp(Vec3(1e-7, -2e-7, 3e-7));
  xs[1].p = Vec3(1e-6, 2e-6, -1e-6);
  xs[1].v = Vec3(-1e-6, 1e-6, 2e-6);
  xs[1].bg = Vec3(1e-7, 0, -1e-7);
  xs[1].ba = Vec3(0, 1e-6, 1e-6);
  std::mt19937 rng(12345);
  std::normal_distribution<double> n(0.0, 1.0);
  auto rv = [&](double s) { return Vec3(s * n(rng), s * n(rng), s * n(rng)); };
  xs[2].R = so3::Exp(rv(1.0));
  xs[2].p = rv(10.0);
  xs[2].v = rv(2.0);
  xs[2].bg = rv(0.01);
  xs[2].ba = rv(0.1);
  return xs;
}

template <>
std::vector<PreintIncrement> CheckPoints<PreintIncrement>() {
  std::vector<PreintIncrement> xs(3);
  xs[1].dR = so3::Exp(Vec3(1e-7, -2e-7, 3e-7));
  xs[1].dp = Vec3(1e-6, 2e-6, -1e-6);
  xs[1].dv = Vec3(-1e-6, 1e-6, 2e-6);
  std::mt19937 rng(54321);
  std::normal_distribution<double> n(0.0, 1.0);
  auto rv = [&](double s) { return Vec3(s * n(rng), s * n(rng), s * n(rng)); };
  xs[2].dR = so3::Exp(rv(0.7));
  xs[2].dp = rv(10.0);
  xs[2].dv = rv(3.0);
  xs[2].dbg = rv(1e-3);
  xs[2].dba = rv(1e-2);
  return xs;
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
