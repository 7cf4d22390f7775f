// What tests/cli/refcase_anchor.cpp (imuconv refcase --anchor NAME against the anchor files)
// shares with a system's own rule for judging its anchor: a system whose output needs more than
// the generic field-by-field comparison (fields an eigen-solver chooses, methods a build may
// lack) declares its rule in a file of its own, tests/cli/refcase_anchor_<system>.cpp, with
// IMUCONV_REFCASE_ANCHOR_RULE; no shared file names the system.
#pragma once

#include <map>
#include <nlohmann/json.hpp>
#include <string>

#include "declared_facts.h"

namespace imuconv::test::refcase_anchor {

/// Every field: 1e-8 by the metric of J. Huai, "IMU Propagation as Preintegration" (relative
/// above 1e-4, absolute below; tests/reference/anchors.h explains the bound: round-off of the
/// same formulas accumulated over 2000 steps).
inline constexpr double kFieldTol = 1e-8;

/// The worst difference per field (array indices dropped from the pointer), printed per anchor.
using FieldWorst = std::map<std::string, double>;

/// A system's rule, run on each case before the generic comparison: it judges what it must
/// judge its own way, records the worst differences in `worst`, and removes those fields from
/// both documents (or, for fields the output cannot have here, from the anchor) so that the
/// generic rule compares the rest. `label` names the anchor and the case for messages.
using AnchorRule = void (*)(nlohmann::json& anchor, nlohmann::json& out, const std::string& label,
                            FieldWorst& worst);
struct AnchorRules {
  using Facts = AnchorRule;
  static constexpr const char* kWhat = "refcase anchor rule";
};

}  // namespace imuconv::test::refcase_anchor

/// Declares RULE (an AnchorRule) for the anchor NAME (the --anchor name, a string); STEM is an
/// identifier unique to the file (its system's name).
#define IMUCONV_REFCASE_ANCHOR_RULE(STEM, NAME, RULE)                                    \
  [[maybe_unused]] static const bool STEM##_refcase_anchor_rule_declared =               \
      ::imuconv::test::DeclaredFacts<::imuconv::test::refcase_anchor::AnchorRules>::Add( \
          NAME, RULE, {__FILE__, __LINE__})
