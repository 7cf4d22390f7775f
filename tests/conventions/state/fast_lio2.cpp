// `fast_lio2` (state): the generic suite, its conversions derived by hand, and its retraction
// against IKFoM's boxplus as imuconv's FAST-LIO2 kernel writes it on the 23-dimensional state
// (kernels/fast_lio2.h: FastLio2Boxplus, the operation the anchor test reproduces FAST-LIO's
// covariance in), with the 15 dimensions embedded and the extrinsic and gravity ones zero.
#include <gtest/gtest.h>

#include "../convention_suite.h"
#include "imuconv/kernels/fast_lio2.h"
#include "imuconv/kernels/system_state.h"

IMUCONV_STATE_CONVENTION(fast_lio2, "p theta v bg ba");

namespace {

using namespace imuconv::test::conventions;
namespace k = imuconv::kernels;

TEST(StateStructure, LeftToFastLio2) {
  // Right, body-frame rotation: R^ Exp(drot) = Exp(R^ drot) R^, so drot = R^T dtheta_left;
  // position and velocity in the world frame like left's, biases in place.
  ExpectConversion("left", "fast_lio2", [](const ImuState& x) -> BlockEntries {
    return {{"theta", x.R.transpose()}};
  });
}

TEST(StateStructure, FastLio2ToForsterDiffersInPositionFrame) {
  // Same right rotation and world velocity; Forster's position is in the body frame.
  ExpectConversion("fast_lio2", "forster", [](const ImuState& x) -> BlockEntries {
    return {{"p", x.R.transpose()}};
  });
}

TEST(StateStructure, FastLio2ToOpenVinsJplIsAPermutation) {
  // OpenVINS's JPL error is a right rotation too (2 atan(s/2)/s = 1 + O(s^2)), with world
  // position and velocity: to first order the two charts differ only in block order.
  ExpectConversion("fast_lio2", "openvins_jpl", [](const ImuState&) -> BlockEntries { return {}; });
}

// The kernel's boxplus and the plugin's retract: the same operations on the same numbers in
// another order (a quaternion product against a matrix product): rounding, 1e-13 on entries
// of size up to |p| ~ 30.
constexpr double kBoxplusTol = 1e-13;

TEST(FastLio2Chart, RetractIsIkfomBoxplusOnTheFifteenDimensions) {
  const auto conv = Plugins().state_convention("fast_lio2");
  for (const ImuState& x : imuconv::test::TestStates()) {
    for (double scale : {1e-6, 0.3}) {
      const Vec15 d = imuconv::test::RandVec15(scale);
      using S = k::FastLio2State;
      const S s = k::SystemStateOf(x, &S::pos, &S::rot, &S::vel, &S::bg, &S::ba);
      k::Vec23 d23 = k::Vec23::Zero();
      d23.segment<3>(k::kFastLio2Pos) = d.segment<3>(0);
      d23.segment<3>(k::kFastLio2Rot) = d.segment<3>(3);
      d23.segment<3>(k::kFastLio2Vel) = d.segment<3>(6);
      d23.segment<3>(k::kFastLio2Bg) = d.segment<3>(9);
      d23.segment<3>(k::kFastLio2Ba) = d.segment<3>(12);
      const k::FastLio2State e = k::FastLio2Boxplus(s, d23);
      ImuState y;
      conv->retract(x, d, y);
      EXPECT_LE((y.R - e.rot.toRotationMatrix()).cwiseAbs().maxCoeff(), kBoxplusTol);
      EXPECT_LE((y.p - e.pos).cwiseAbs().maxCoeff(), kBoxplusTol);
      EXPECT_LE((y.v - e.vel).cwiseAbs().maxCoeff(), kBoxplusTol);
      EXPECT_LE((y.bg - e.bg).cwiseAbs().maxCoeff(), kBoxplusTol);
      EXPECT_LE((y.ba - e.ba).cwiseAbs().maxCoeff(), kBoxplusTol);
      // and local is the kernel's boxminus on those blocks
      Vec15 back;
      conv->local(x, y, back);
      const k::Vec23 back23 = k::FastLio2Boxminus(e, s);
      EXPECT_LE((back.segment<3>(3) - back23.segment<3>(k::kFastLio2Rot)).cwiseAbs().maxCoeff(),
                kBoxplusTol);
      EXPECT_LE((back.segment<3>(0) - back23.segment<3>(k::kFastLio2Pos)).cwiseAbs().maxCoeff(),
                kBoxplusTol);
    }
  }
}

}  // namespace
