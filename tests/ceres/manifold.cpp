// StateManifold in every registered state convention: Plus and Minus invert each other, and
// the Jacobians are those of Plus and Minus, with MinusJacobian * PlusJacobian = I.
#include <gtest/gtest.h>

#include <array>

#include "ceres_problem.h"
#include "imuconv_test.h"

namespace imuconv::ceres_test {
namespace {

using Block = std::array<double, kStateBlockSize>;

// States whose rotation is at most 1.5 rad from the identity, and one far from it (2.5 rad):
// the quaternion of the block keeps w > 0.3, so that the w >= 0 sign choice of ToStateBlock
// cannot flip it between two central-difference points.
std::vector<ImuState> ManifoldStates() {
  std::vector<ImuState> xs(3);
  xs[1].R = so3::Exp(Vec3(0.3, -1.2, 0.7));
  xs[1].p = Vec3(3.0, -2.0, 1.0);
  xs[1].v = Vec3(1.0, 0.5, -0.3);
  xs[1].bg = Vec3(0.01, -0.02, 0.005);
  xs[1].ba = Vec3(0.1, 0.2, -0.1);
  xs[2] = xs[1];
  xs[2].R = so3::Exp(Vec3(2.0, 1.0, -1.0).normalized() * 2.5);
  return xs;
}

TEST(CeresStateManifold, PlusAndMinusInvertEachOtherInEveryConvention) {
  const Registry& reg = test::Plugins();
  std::mt19937 rng(7);
  std::normal_distribution<double> n(0.0, 0.1);
  for (const std::string& id : reg.ids(PluginKind::StateConvention)) {
    const StateManifold M(reg, id);
    for (const ImuState& x : ManifoldStates()) {
      Block bx, by;
      ToStateBlock(x, bx.data());
      Vec15 d, back;
      for (int i = 0; i < 15; ++i) d[i] = n(rng);
      ASSERT_TRUE(M.Plus(bx.data(), d.data(), by.data()));
      ASSERT_TRUE(M.Minus(by.data(), bx.data(), back.data()));
      // Round trip of a retract and a local of 0.1-sized steps: a few ulps of the entries
      // (each a sum of products of O(1) numbers), 1e-12 leaves a margin of 1e3.
      EXPECT_LT((back - d).cwiseAbs().maxCoeff(), 1e-12) << id;
    }
  }
}

TEST(CeresStateManifold, JacobiansAreThoseOfPlusAndMinusAndInvertEachOther) {
  const Registry& reg = test::Plugins();
  const double h = 1e-6;
  for (const std::string& id : reg.ids(PluginKind::StateConvention)) {
    const StateManifold M(reg, id);
    ASSERT_EQ(M.convention(), id);
    for (const ImuState& x : ManifoldStates()) {
      Block bx;
      ToStateBlock(x, bx.data());
      Eigen::Matrix<double, 16, 15, Eigen::RowMajor> P;
      Eigen::Matrix<double, 15, 16, Eigen::RowMajor> Mi;
      ASSERT_TRUE(M.PlusJacobian(bx.data(), P.data()));
      ASSERT_TRUE(M.MinusJacobian(bx.data(), Mi.data()));
      // The registry's conversion Jacobians are analytic (verified at load) or Ridders'
      // differences (~1e-12 relative): the product is I to well under 1e-9.
      EXPECT_LT((Mi * P - Mat15::Identity()).cwiseAbs().maxCoeff(), 1e-9) << id;

      // Central differences with h = 1e-6 of maps with O(1) second derivatives: O(h^2) = 1e-12
      // truncation, round-off 1e-16 / 1e-6 = 1e-10; 1e-7 flags any wrong entry (O(1e-1) or more).
      Eigen::Matrix<double, 16, 15> P_num;
      for (int i = 0; i < 15; ++i) {
        Vec15 d = Vec15::Zero();
        Block bp, bm;
        d[i] = h;
        M.Plus(bx.data(), d.data(), bp.data());
        d[i] = -h;
        M.Plus(bx.data(), d.data(), bm.data());
        for (int a = 0; a < 16; ++a) P_num(a, i) = (bp[a] - bm[a]) / (2.0 * h);
      }
      EXPECT_LT((P - P_num).cwiseAbs().maxCoeff(), 1e-7) << id;
      Eigen::Matrix<double, 15, 16> M_num;
      for (int a = 0; a < 16; ++a) {
        Block yp = bx, ym = bx;
        yp[a] += h;
        ym[a] -= h;
        Vec15 dp, dm;
        M.Minus(yp.data(), bx.data(), dp.data());
        M.Minus(ym.data(), bx.data(), dm.data());
        M_num.col(a) = (dp - dm) / (2.0 * h);
      }
      EXPECT_LT((Mi - M_num).cwiseAbs().maxCoeff(), 1e-7) << id;
    }
  }
}

TEST(CeresStateBlock, RoundTripAndQuaternionSign) {
  for (const ImuState& x : test::TestStates()) {
    Block b;
    ToStateBlock(x, b.data());
    EXPECT_GE(b[block_idx::q], 0.0);
    const ImuState y = FromStateBlock(b.data());
    // One quaternion conversion each way: a few ulps.
    EXPECT_LT((y.R - x.R).cwiseAbs().maxCoeff(), 1e-14);
    EXPECT_EQ(y.p, x.p);
    EXPECT_EQ(y.v, x.v);
    EXPECT_EQ(y.bg, x.bg);
    EXPECT_EQ(y.ba, x.ba);
  }
  // A block whose quaternion is not unit (a user's initial value) reads as the unit one.
  Block b{};
  b[block_idx::q] = 2.0;
  EXPECT_LT((FromStateBlock(b.data()).R - Mat3::Identity()).cwiseAbs().maxCoeff(), 1e-15);
}

TEST(CeresStateManifold, UnknownConventionIsAnError) {
  EXPECT_THROW(StateManifold(test::Plugins(), "no_such_chart"), Error);
}

}  // namespace
}  // namespace imuconv::ceres_test
