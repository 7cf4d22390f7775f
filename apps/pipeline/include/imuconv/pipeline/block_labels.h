// The navigation and bias blocks of a chart's labels, each in the chart's order (internal).
#pragma once

#include <string>
#include <vector>

namespace imuconv::pipeline {

/// Non-bias and bias labels of a chart, in its order.
inline std::vector<std::string> NavLabels(const std::vector<std::string>& blocks) {
  std::vector<std::string> out;
  for (const auto& b : blocks)
    if (b != "bg" && b != "ba") out.push_back(b);
  return out;
}
inline std::vector<std::string> BiasLabels(const std::vector<std::string>& blocks) {
  std::vector<std::string> out;
  for (const auto& b : blocks)
    if (b == "bg" || b == "ba") out.push_back(b);
  return out;
}

}  // namespace imuconv::pipeline
