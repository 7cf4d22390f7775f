// A Monte Carlo input from a reference case (tests/data/reference/cases): its first `seconds`
// of samples (every sample up to the first time + seconds, with 1e-9 s of slack so that a knot
// at exactly that time, as written in the case, is kept), its noise and its start bias as the
// estimate. Short windows keep the montecarlo tests at about a second each.
#pragma once

#include <cstring>
#include <string>

#include "imuconv_test.h"
#include "montecarlo.h"
#include "reference_case.h"

namespace imuconv::montecarlo {

inline Input CaseInput(const std::string& id, double seconds) {
  const nlohmann::json c = test::CaseJson(id);
  Input in;
  for (const ImuSample& s : test::CaseSamples(c))
    if (in.samples.empty() || s.t <= in.samples.front().t + seconds + 1e-9) in.samples.push_back(s);
  in.noise = test::CaseNoise(c);
  in.bg = test::JsonVec3(c.at("state_s").at("bg"));
  in.ba = test::JsonVec3(c.at("state_s").at("ba"));
  return in;
}

/// Whether two matrices hold the same doubles bit for bit (a path's results "by construction").
inline bool SameBits(const Mat15& a, const Mat15& b) {
  return std::memcmp(a.data(), b.data(), sizeof(double) * 225) == 0;
}

}  // namespace imuconv::montecarlo
