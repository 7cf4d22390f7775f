// What a convention plugin is made of besides its own derivation: the block order declared
// once as a template argument (order(), offsets and the bias blocks derive from it) and the
// block-sparse Jacobians to and from the reference chart built from per-block 3x3 maps.
//
//   constexpr imuconv::BlockOrder kOrder{Block::theta, Block::p, Block::v, Block::ba, Block::bg};
//   class MyChart : public imuconv::plugin::StateChart<kOrder> {
//     void retract(...) const noexcept override { ...; RetractBiases(x, d, y); }
//     bool J_ref_this(const ImuState& x, Mat15& J) const noexcept override {
//       return RefThis(J, {{Block::theta, x.R}, {Block::p, x.R}});  // other blocks: identity
//     }
//   };
//   IMUCONV_PLUGIN(StateConvention, MyChart, "my_chart", "1.0.0", "...")
#pragma once

#include <initializer_list>
#include <utility>

#include "imuconv/chart.h"
#include "imuconv/reference_charts.h"
#include "imuconv/so3.h"

namespace imuconv::plugin {

/// One 3x3 block of a Jacobian between this chart and the reference chart: the block that
/// maps `block` of one chart to the same `block` of the other.
using BlockMap = std::pair<Block, Mat3>;

template <class Value, const BlockOrder& Order>
class ConventionChart : public Chart<Value> {
  static_assert(Order.is_permutation(), "a block order names p, theta, v, bg and ba once each");

 public:
  BlockOrder order() const noexcept final { return Order; }

 protected:
  using Ref = ReferenceChart<Value>;
  // Offsets of this chart's blocks in its perturbation vector.
  static constexpr int p = Order.offset(Block::p), theta = Order.offset(Block::theta), v = Order.offset(Block::v),
                       bg = Order.offset(Block::bg), ba = Order.offset(Block::ba);

  /// J_ref_this as the permutation between the two orders (identity blocks), with the given
  /// blocks replaced: J(ref(b), this(b)) = M. Always returns true (analytic Jacobian given).
  static bool RefThis(Mat15& J, std::initializer_list<BlockMap> blocks) noexcept {
    Permutation(J, Ref::order, Order, blocks);
    return true;
  }
  /// J_this_ref likewise: J(this(b), ref(b)) = M.
  static bool ThisRef(Mat15& J, std::initializer_list<BlockMap> blocks) noexcept {
    Permutation(J, Order, Ref::order, blocks);
    return true;
  }
  /// The 3x3 block of J_ref_this at (reference block `row`, this chart's block `col`), for
  /// the blocks off the permutation.
  static Eigen::Block<Mat15, 3, 3> RefThisBlock(Mat15& J, Block row, Block col) noexcept {
    return J.template block<3, 3>(Ref::order.offset(row), Order.offset(col));
  }
  static Eigen::Block<Mat15, 3, 3> ThisRefBlock(Mat15& J, Block row, Block col) noexcept {
    return J.template block<3, 3>(Order.offset(row), Ref::order.offset(col));
  }

 private:
  static void Permutation(Mat15& J, const BlockOrder& rows, const BlockOrder& cols,
                          std::initializer_list<BlockMap> blocks) noexcept {
    J.setZero();
    for (int k = 0; k < kBlockCount; ++k) {
      const Block b = static_cast<Block>(k);
      J.template block<3, 3>(rows.offset(b), cols.offset(b)).setIdentity();
    }
    for (const BlockMap& m : blocks) J.template block<3, 3>(rows.offset(m.first), cols.offset(m.first)) = m.second;
  }
};

/// A state convention with additive biases, b = b^ + db (all but exotic ones).
template <const BlockOrder& Order>
class StateChart : public ConventionChart<ImuState, Order> {
 protected:
  using Base = ConventionChart<ImuState, Order>;
  static void RetractBiases(const ImuState& x, const Vec15& d, ImuState& y) noexcept {
    y.bg = x.bg + d.template segment<3>(Base::bg);
    y.ba = x.ba + d.template segment<3>(Base::ba);
  }
  static void LocalBiases(const ImuState& x, const ImuState& y, Vec15& d) noexcept {
    d.template segment<3>(Base::bg) = y.bg - x.bg;
    d.template segment<3>(Base::ba) = y.ba - x.ba;
  }
};

/// An increment convention; its bias entry is Delta b = Delta b^ + db (BiasSign +1) or, with
/// the sign of the paper's eq. preint-error-db and of GTSAM, Delta b^ - db (BiasSign -1).
template <const BlockOrder& Order, int BiasSign>
class IncrementChart : public ConventionChart<PreintIncrement, Order> {
  static_assert(BiasSign == 1 || BiasSign == -1, "the bias entry is added or subtracted");

 protected:
  using Base = ConventionChart<PreintIncrement, Order>;
  /// As ConventionChart's, with the bias blocks BiasSign * I.
  static bool RefThis(Mat15& J, std::initializer_list<BlockMap> blocks) noexcept {
    Base::RefThis(J, blocks);
    if (BiasSign < 0) {
      Base::RefThisBlock(J, Block::bg, Block::bg) = -Mat3::Identity();
      Base::RefThisBlock(J, Block::ba, Block::ba) = -Mat3::Identity();
    }
    return true;
  }
  static bool ThisRef(Mat15& J, std::initializer_list<BlockMap> blocks) noexcept {
    Base::ThisRef(J, blocks);
    if (BiasSign < 0) {
      Base::ThisRefBlock(J, Block::bg, Block::bg) = -Mat3::Identity();
      Base::ThisRefBlock(J, Block::ba, Block::ba) = -Mat3::Identity();
    }
    return true;
  }
  static void RetractBiases(const PreintIncrement& x, const Vec15& d, PreintIncrement& y) noexcept {
    if (BiasSign > 0) {
      y.dbg = x.dbg + d.template segment<3>(Base::bg);
      y.dba = x.dba + d.template segment<3>(Base::ba);
    } else {
      y.dbg = x.dbg - d.template segment<3>(Base::bg);
      y.dba = x.dba - d.template segment<3>(Base::ba);
    }
  }
  static void LocalBiases(const PreintIncrement& x, const PreintIncrement& y, Vec15& d) noexcept {
    if (BiasSign > 0) {
      d.template segment<3>(Base::bg) = y.dbg - x.dbg;
      d.template segment<3>(Base::ba) = y.dba - x.dba;
    } else {
      d.template segment<3>(Base::bg) = x.dbg - y.dbg;
      d.template segment<3>(Base::ba) = x.dba - y.dba;
    }
  }
};

/// The names a convention plugin is written in: `using namespace imuconv::plugin::prelude;`.
namespace prelude {
using imuconv::Block;
using imuconv::BlockOrder;
using imuconv::ImuState;
using imuconv::Mat15;
using imuconv::Mat3;
using imuconv::PreintIncrement;
using imuconv::Vec15;
using imuconv::Vec3;
namespace so3 = imuconv::so3;
}  // namespace prelude

}  // namespace imuconv::plugin
