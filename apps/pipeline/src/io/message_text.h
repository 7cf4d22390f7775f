// Small text helpers for messages and summaries, shared by the pipeline's sources (internal).
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

}  // namespace imuconv::pipeline
