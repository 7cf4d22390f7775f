// The verdict on one measurement and its findings in plain words, from the explanation under
// its declaration and the best explanation found (explain.h). The tolerances, and why they
// are what they are, are in verdict.cpp (and docs/check.md).
#pragma once

#include <string>
#include <vector>

#include "imuconv/check/explain.h"

namespace imuconv::check {

/// The tolerances check applies (kCheckTolerances in verdict.cpp).
const Tolerances& CheckTolerances();

enum class Verdict { consistent, inconsistent };

struct Judgement {
  Verdict verdict = Verdict::inconsistent;
  std::vector<std::string> findings;
};

/// consistent: the numbers are within tolerance under the declaration (the undeclared parts
/// taken as found). inconsistent: otherwise, with the fix when another explanation is within
/// tolerance, or the nearest explanation, its d and its block findings (block_findings.h) when
/// none is. `nearest` is the best explanation's candidates (for the diagonal ratios of a
/// covariance nothing explains); `sample_period` names scale factors (x1/dt).
Judgement Judge(const Constraints& declared, const Explanation& under_declaration,
                const Explanation& best, const SchemeCandidates& nearest, const UserNumbers& user,
                double sample_period);

/// "[theta, p, v, ba, bg]".
std::string BlockList(const std::vector<std::string>& blocks);

}  // namespace imuconv::check
