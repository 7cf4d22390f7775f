// The state conventions' suite class, instantiated in each convention's file, and the
// hand-derived expectations their structure tests build.
#pragma once

#include "../convention_suite.h"

IMUCONV_DECLARE_CONVENTION_SUITE(StateConventionSuite);

namespace imuconv::test::state {

// What every test file of the folder uses (`using namespace imuconv::test::state;`).
using imuconv::ImuState;
using imuconv::Mat15;
using imuconv::Mat3;
using imuconv::Vec15;
using imuconv::Vec3;
using imuconv::test::Plugins;
using imuconv::test::RelErr;
using imuconv::test::StateKind;
namespace so3 = imuconv::so3;

/// Expected conversion(from, to, x) built block by block; compares with the registry's.
inline void ExpectConversion(const char* from, const char* to, const ImuState& x, const Mat15& expected) {
  const Mat15 J = Plugins().conversion(from, to, x);
  EXPECT_LE(RelErr(J, expected), kStructureTol) << from << " -> " << to << "\ngot\n" << J << "\nexpected\n" << expected;
}

inline BlockBuilder Expect(const char* from, const char* to) {
  return BlockBuilder(Plugins().state_convention(to)->labels(), Plugins().state_convention(from)->labels());
}

inline const Mat3 I3 = Mat3::Identity();

}  // namespace imuconv::test::state
