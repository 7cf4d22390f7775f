// The cost declaration of a residual plugin, checked, and the sink that reads what it names.
#include "imuconv/residual_cost_outputs.h"

#include <algorithm>
#include <cstring>
#include <exception>

#include "imuconv/block_order.h"

namespace imuconv {

namespace {

// Largest column count a plugin may declare a Jacobian with (the registry bounds the
// residual's dimension by 1000 the same way).
constexpr int kMaxColumns = 1000;

}  // namespace

bool ReadCostName(const char* s, std::string& out) {
  if (s == nullptr) return false;
  const std::size_t n = strnlen(s, kMaxCostNameLength + 1);
  if (n == 0 || n > kMaxCostNameLength) return false;
  out.assign(s, n);
  return true;
}

ResidualCostOutputs ResolveResidualCost(const Registry& reg, const ResidualFactor& factor) {
  ResidualCostOutputs o;
  if (!ReadCostName(factor.id(), o.id)) o.id = "?";
  const std::string where = "residual plugin '" + o.id + "'";
  const ResidualCostSpec* spec = factor.cost_spec();
  if (spec == nullptr)
    throw Error(where +
                " declares no cost (ResidualFactor::cost_spec() is null): it cannot be a Ceres "
                "cost");
  o.n = factor.degrees_of_freedom();
  if (o.n < 1 || o.n > 1000)
    throw Error(where + ": degrees_of_freedom() is " + std::to_string(o.n) +
                " (expected 1 to 1000, the residual's dimension)");
  const auto add_output = [&](const char* name, int min_cols, const char* what) {
    std::string s;
    if (!ReadCostName(name, s))
      throw Error(where + ": cost_spec()'s " + what +
                  " is not a name (null, empty or longer than 256 bytes)");
    for (std::size_t k = 0; k < o.names.size(); ++k)
      if (o.names[k] == s) {  // the residual's (k = 0) is refused by the callers
        o.min_cols[k] = std::max(o.min_cols[k], min_cols);
        return static_cast<int>(k);
      }
    o.names.push_back(s);
    o.min_cols.push_back(min_cols);
    return static_cast<int>(o.names.size() - 1);
  };
  add_output(spec->residual, 1, "residual");
  if (!ReadCostName(spec->state_convention, o.state_convention))
    throw Error(where + ": cost_spec()'s state_convention is not an id");
  if (!reg.has(PluginKind::StateConvention, o.state_convention)) {
    try {
      (void)reg.state_convention(o.state_convention);  // its message lists the known ones
    } catch (const Error& e) {
      throw Error(where + ": its Jacobians are declared in state convention '" +
                  o.state_convention + "', which is not registered: " + e.what());
    }
  }
  o.weighting = spec->weighting;
  switch (spec->weighting) {
    case ResidualWeighting::SqrtInformation:
    case ResidualWeighting::Information:
      o.weighting_output = add_output(spec->weighting_matrix, o.n, "weighting_matrix");
      if (o.weighting_output == 0)
        throw Error(where + ": cost_spec() names the residual as its weighting matrix");
      break;
    case ResidualWeighting::MeasurementCovariance:
      if (spec->weighting_matrix != nullptr)
        throw Error(where +
                    ": cost_spec() names a weighting matrix for the measurement's covariance "
                    "weighting (expected null)");
      break;
    default:
      throw Error(where + ": cost_spec()'s weighting " +
                  std::to_string(static_cast<int>(spec->weighting)) + " is not one of 1, 2, 3");
  }
  const BlockOrder order = reg.state_convention(o.state_convention)->order();
  const auto resolve = [&](const ResidualJacobianColumns* cols, const char* state,
                           std::vector<ResidualJacobianPlacement>& out) {
    bool seen[kBlockCount] = {};
    for (int k = 0; k < kResidualJacobianBlocks; ++k) {
      const ResidualJacobianColumns& c = cols[k];
      if (c.matrix == nullptr) continue;
      const char* block = BlockName(c.block);
      if (block == nullptr)
        throw Error(where + ": cost_spec()'s " + state + " block " + std::to_string(k) +
                    " names no tangent block (p, theta, v, bg, ba)");
      const int b = static_cast<int>(c.block);
      if (seen[b])
        throw Error(where + ": cost_spec() gives the " + state + " state's block '" + block +
                    "' twice");
      seen[b] = true;
      if (c.first_column < 0 || c.first_column > kMaxColumns - 3)
        throw Error(where + ": cost_spec()'s " + state + " block '" + block +
                    "' starts at column " + std::to_string(c.first_column) + " (expected 0 to " +
                    std::to_string(kMaxColumns - 3) + ")");
      ResidualJacobianPlacement j;
      j.output = add_output(c.matrix, c.first_column + 3, "Jacobian matrix");
      if (j.output == 0)
        throw Error(where + ": cost_spec() names the residual as a Jacobian matrix");
      j.first_column = c.first_column;
      j.offset = order.offset(c.block);
      if (j.offset < 0)
        throw Error(where + ": state convention '" + o.state_convention + "' has no block '" +
                    block + "'");
      out.push_back(j);
    }
  };
  resolve(spec->start, "start", o.start);
  resolve(spec->end, "end", o.end);
  return o;
}

ResidualCostOutputSink::ResidualCostOutputSink(const ResidualCostOutputs& outputs,
                                               ResidualOutputValues& into)
    : outputs_(outputs), into_(into) {
  into_.values.resize(outputs_.names.size());
  into_.written.assign(outputs_.names.size(), false);
}

void ResidualCostOutputSink::begin_group(const char* name) noexcept {
  if (!problem_.empty()) return;
  try {
    std::string s;
    if (!ReadCostName(name, s)) {
      problem_ = "a group without a name (null, empty or too long)";
      return;
    }
    groups_.push_back(path_.size());
    path_ += s;
    path_ += '/';
  } catch (const std::exception&) {
    problem_ = "out of memory while reading its outputs";
  }
}

void ResidualCostOutputSink::end_group() noexcept {
  if (!problem_.empty()) return;
  if (groups_.empty()) {
    problem_ = "end_group() without an open group";
    return;
  }
  path_.resize(groups_.back());
  groups_.pop_back();
}

int ResidualCostOutputSink::Find(const char* name) {
  const std::size_t n = strnlen(name, kMaxCostNameLength + 1);
  for (std::size_t k = 0; k < outputs_.names.size(); ++k) {
    const std::string& want = outputs_.names[k];
    if (want.size() == path_.size() + n && want.compare(0, path_.size(), path_) == 0 &&
        want.compare(path_.size(), n, name, n) == 0)
      return static_cast<int>(k);
  }
  return -1;
}

void ResidualCostOutputSink::Keep(const char* name, const double* data, int rows, int cols,
                                  bool is_vector) noexcept {
  if (!problem_.empty()) return;
  try {
    if (name == nullptr) {
      problem_ = "an output without a name (null)";
      return;
    }
    const int k = Find(name);
    if (k < 0) return;  // not part of the cost
    const std::string& what = outputs_.names[k];
    if (into_.written[k]) {
      problem_ = "'" + what + "' is written twice";
      return;
    }
    const int n = outputs_.n;
    const bool residual = (k == 0);
    if (residual != is_vector || rows != n ||
        (residual ? cols != 1 : cols < outputs_.min_cols[k])) {
      problem_ = "'" + what + "' is " + (is_vector ? "a vector of " : "a matrix ") +
                 std::to_string(rows) + (is_vector ? "" : "x" + std::to_string(cols)) +
                 " (its cost declaration expects " +
                 (residual ? "a vector of " + std::to_string(n)
                           : "a matrix with " + std::to_string(n) + " rows and at least " +
                                 std::to_string(outputs_.min_cols[k]) + " columns") +
                 ")";
      return;
    }
    if (data == nullptr) {
      problem_ = "'" + what + "' has no numbers (null)";
      return;
    }
    RowMajorMatrixXd& v = into_.values[k];
    v = Eigen::Map<const RowMajorMatrixXd>(data, rows, cols);
    if (!v.allFinite()) {
      problem_ = "'" + what + "' is not finite";
      return;
    }
    into_.written[k] = true;
  } catch (const std::exception&) {
    problem_ = "out of memory while reading its outputs";
  }
}

void ResidualCostOutputSink::vector(const char* name, const double* values, int size) noexcept {
  Keep(name, values, size, 1, true);
}

void ResidualCostOutputSink::matrix(const char* name, const double* row_major, int rows,
                                    int cols) noexcept {
  Keep(name, row_major, rows, cols, false);
}

std::string ResidualCostOutputSink::Finish() const {
  if (!problem_.empty()) return problem_;
  for (std::size_t k = 0; k < outputs_.names.size(); ++k)
    if (!into_.written[k])
      return "it wrote no '" + outputs_.names[k] + "', which its cost declaration names" +
             (static_cast<int>(k) == outputs_.weighting_output
                  ? " as its weighting (a measurement without noise has none)"
                  : "");
  return "";
}

std::string EvaluateResidualCost(const ResidualFactor& factor, const ResidualCostOutputs& outputs,
                                 const Preintegrated& m, const ImuState& x_s, const ImuState& x_e,
                                 const Vec3& gravity, ResidualOutputValues& values) noexcept {
  try {
    ResidualCostOutputSink sink(outputs, values);
    const Status st = factor.evaluate(m, x_s, x_e, gravity, sink);
    if (!st.ok()) return st.message();
    return sink.Finish();
  } catch (const std::exception&) {
    return "out of memory while evaluating it";
  }
}

void AssembleResidualJacobian(const ResidualCostOutputs& outputs,
                              const ResidualOutputValues& values,
                              const std::vector<ResidualJacobianPlacement>& blocks,
                              Eigen::MatrixXd& H) {
  H.setZero(outputs.n, 15);
  for (const ResidualJacobianPlacement& b : blocks)
    H.middleCols<3>(b.offset) = values.values[b.output].middleCols<3>(b.first_column);
}

}  // namespace imuconv
