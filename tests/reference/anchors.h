// What the tests against other systems' own numbers (tests/data/reference/anchors) share:
// the bounds and the anchors' construction of the preintegration input.
//
// The bound on every computed field is the anchors' 1e-8 by the metric of J. Huai, "IMU
// Propagation as Preintegration" (relative above 1e-4, absolute below): the same scheme
// computed in another order (and here with FMA, upstream without) differs by rounding only,
// accumulated over 2000 steps. The metric leaves entries below 1e-4 unchecked, so covariances
// are also compared on the correlation scale and Jacobians relative to each entry above a
// floor of 1e-4 of the largest (scale_aware.h), at 1e-9: a sign or a factor in any block
// gives O(1) there.
#pragma once

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <string>

#include "../integrators/integrator_cases.h"
#include "imuconv/preintegrator.h"
#include "reference_case.h"

namespace imuconv::test {

constexpr double kAnchorMetricTol = 1e-8;
constexpr double kAnchorScaledTol = 1e-9;

/// The fixture of a test over the reference cases (its parameter: a case id) against one
/// system's anchors: the case, as `Load` reads it, and that system's anchor file for it, both
/// read when the test is constructed (a missing or unreadable file fails the test there).
template <typename CaseT, CaseT (*Load)(const std::string&)>
class AnchorFixture : public ::testing::TestWithParam<const char*> {
 protected:
  /// `system`: the anchors' folder, as AnchorJson takes it.
  explicit AnchorFixture(const char* system)
      : anchor_(AnchorJson(system, GetParam())),
        case_(Load(GetParam())),
        inputs_(anchor_.at("inputs")) {}
  nlohmann::json anchor_;
  CaseT case_;
  const nlohmann::json& inputs_;  ///< the anchor's `inputs`: what the system was run with
};

/// The case as an ImuCase.
using AnchorCaseTest = AnchorFixture<ImuCase, LoadCase>;
/// The case as its JSON document (for the tests that take its samples and noise from the
/// document, as the anchors' inputs were written).
using AnchorCaseJsonTest = AnchorFixture<nlohmann::json, CaseJson>;

/// The preintegration anchors' input: the whole case from its first sample to its last, at
/// the bias estimate given (the case's start biases, or a changed one).
inline PreintegrationInput AnchorInput(const ImuCase& c, const Vec3& bg, const Vec3& ba) {
  return PreintegrationInputOf(MakeInput(c, c.samples.front().t, c.samples.back().t).window, bg, ba,
                               c.noise);
}

}  // namespace imuconv::test
