// Small text and block-label helpers shared by the pipeline's sources (internal).
#pragma once

#include <iomanip>
#include <sstream>
#include <string>
#include <vector>

namespace imuconv::pipeline {

inline std::string Join(const std::vector<std::string>& xs) {
  std::string s;
  for (const auto& x : xs) s += (s.empty() ? "" : ", ") + x;
  return s;
}

inline std::string Num(double v, int prec = 6) {
  std::ostringstream o;
  o << std::setprecision(prec) << v;
  return o.str();
}

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
