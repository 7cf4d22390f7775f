#include "imuconv/check/candidates.h"

#include <algorithm>

namespace imuconv::check {
namespace {

const char* const kReference = "preint_reference";

int IndexOf(const std::vector<std::string>& labels, const std::string& label) {
  const auto it = std::find(labels.begin(), labels.end(), label);
  if (it == labels.end()) throw Error("block '" + label + "' is not one of the chart's blocks");
  return static_cast<int>(it - labels.begin());
}

}  // namespace

Eigen::Matrix<double, 15, 1> IncrementEntries(const PreintIncrement& d) {
  Eigen::Matrix<double, 15, 1> e;
  for (int r = 0; r < 3; ++r) e.segment<3>(3 * r) = d.dR.row(r).transpose();
  e.segment<3>(9) = d.dp;
  e.segment<3>(12) = d.dv;
  return e;
}

SchemeCandidates MakeCandidates(const Registry& reg, const std::string& scheme,
                                const Preintegrated& ref) {
  SchemeCandidates out;
  out.scheme = scheme;
  out.delta = IncrementEntries(ref.delta);
  // J in preint_reference rows [theta, p, v], columns [bg, ba], embedded in the 15 rows of the
  // reference chart: the bias estimate does not move the increment's bias blocks.
  Eigen::Matrix<double, 15, 6> J_ref = Eigen::Matrix<double, 15, 6>::Zero();
  J_ref.topRows<9>() = ref.J_bias;
  for (const auto& id : reg.ids(PluginKind::IncrementConvention)) {
    const auto& labels = reg.info(PluginKind::IncrementConvention, id).blocks;
    out.covariances.push_back({id, labels, Express(reg, ref, id).cov});
    // d(chart perturbation)/d(reference perturbation) at the increment times J: the rows of the
    // chart's non-bias blocks, in the chart's order (as Express does for a chart's bias
    // Jacobian, bridge.cpp).
    const Eigen::Matrix<double, 15, 6> J_chart = reg.conversion(kReference, id, ref.delta) * J_ref;
    JacobianCandidate j{id, {}, Mat96::Zero()};
    int row = 0;
    for (int b = 0; b < 5; ++b)
      if (labels[b] != "bg" && labels[b] != "ba") {
        j.J_bg_ba.middleRows<3>(3 * row++) = J_chart.middleRows<3>(3 * b);
        j.rows.push_back(labels[b]);
      }
    out.jacobians.push_back(std::move(j));
  }
  return out;
}

std::array<Eigen::Index, 15> ReorderedIndices(const CovarianceCandidate& c,
                                              const std::vector<std::string>& order) {
  std::array<Eigen::Index, 15> from{};
  for (int b = 0; b < 5; ++b) {
    const int block = IndexOf(c.labels, order[b]);
    for (int r = 0; r < 3; ++r) from[3 * b + r] = 3 * block + r;
  }
  return from;
}

Mat15 Reordered(const CovarianceCandidate& c, const std::vector<std::string>& order) {
  const auto from = ReorderedIndices(c, order);
  Mat15 out;
  for (int j = 0; j < 15; ++j)
    for (int i = 0; i < 15; ++i) out(i, j) = c.cov(from[i], from[j]);
  return out;
}

Mat96 Arranged(const JacobianCandidate& c, const std::vector<std::string>& columns, int sign) {
  Mat96 out;
  for (int k = 0; k < 2; ++k)
    out.middleCols<3>(3 * k) = c.J_bg_ba.middleCols<3>(columns[k] == "bg" ? 0 : 3);
  return static_cast<double>(sign) * out;
}

}  // namespace imuconv::check
