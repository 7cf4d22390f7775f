// The increment conventions' suite class, instantiated in each convention's file, and the
// hand-derived expectations their structure tests build.
#pragma once

#include "../convention_suite.h"

IMUCONV_DECLARE_CONVENTION_SUITE(IncrementConventionSuite);

namespace imuconv::test::increment {

// What every test file of the folder uses (`using namespace imuconv::test::increment;`).
using imuconv::Mat15;
using imuconv::Mat3;
using imuconv::PreintIncrement;
using imuconv::Vec15;
using imuconv::Vec3;
using imuconv::test::Plugins;
using imuconv::test::IncrementKind;
using imuconv::test::RelErr;
namespace so3 = imuconv::so3;

/// Expected increment_conversion(from, to, x) built block by block; compares with the registry's.
inline void ExpectConversion(const char* from, const char* to, const PreintIncrement& x, const Mat15& expected) {
  const Mat15 J = Plugins().increment_conversion(from, to, x);
  EXPECT_LE(RelErr(J, expected), kStructureTol) << from << " -> " << to << "\ngot\n"
                                                                << J << "\nexpected\n" << expected;
}

inline BlockBuilder Expect(const char* from, const char* to) {
  return BlockBuilder(Plugins().increment_convention(to)->labels(), Plugins().increment_convention(from)->labels());
}

inline const Mat3 I3 = Mat3::Identity();

}  // namespace imuconv::test::increment
