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
//
// A chart whose Jacobians are those of a body-frame perturbation of some of the reference's
// blocks states only which, and writes retract and local alone:
//   constexpr std::array kBodyFrame{Block::theta, Block::p};
//   class MyChart : public RotatedBlocksChart<StateChart<kOrder>, kBodyFrame> { retract, local };
// One whose rotation is perturbed on the right and whose p, v are body-frame where listed and
// additive where not is all in that list: `using MyChart = RightRotationChart<..., kBodyFrame>`.
#pragma once

#include <array>
#include <cstddef>
#include <initializer_list>
#include <type_traits>
#include <utility>

#include "imuconv/chart.h"
#include "imuconv/reference_charts.h"
#include "imuconv/so3.h"

namespace imuconv::plugin {

/// One 3x3 block of a Jacobian between this chart and the reference chart: the block that
/// maps `block` of one chart to the same `block` of the other.
using BlockMap = std::pair<Block, Mat3>;

/// BiasSign: the bias entry is b^ + db (+1, every state chart) or, with the sign of the
/// paper's eq. preint-error-db and of GTSAM's increments, Delta b^ - db (-1).
template <class Value, const BlockOrder& Order, int BiasSign>
class ConventionChart : public Chart<Value> {
  static_assert(Order.is_permutation(), "a block order names p, theta, v, bg and ba once each");
  static_assert(BiasSign == 1 || BiasSign == -1, "the bias entry is added or subtracted");

 public:
  BlockOrder order() const noexcept final { return Order; }

 protected:
  using Ref = ReferenceChart<Value>;
  // Offsets of this chart's blocks in its perturbation vector.
  static constexpr int p = Order.offset(Block::p), theta = Order.offset(Block::theta),
                       v = Order.offset(Block::v), bg = Order.offset(Block::bg),
                       ba = Order.offset(Block::ba);

  /// J_ref_this as the permutation between the two orders (identity blocks, BiasSign * I on
  /// the biases), with the given blocks replaced: J(ref(b), this(b)) = M. Always returns true
  /// (analytic Jacobian given).
  static bool RefThis(Mat15& J, std::initializer_list<BlockMap> blocks) noexcept {
    Permutation(J, Ref::order, Order, blocks);
    return true;
  }
  /// J_this_ref likewise: J(this(b), ref(b)) = M.
  static bool ThisRef(Mat15& J, std::initializer_list<BlockMap> blocks) noexcept {
    Permutation(J, Order, Ref::order, blocks);
    return true;
  }
  /// The Jacobians of a chart whose blocks `rotated` are the reference's seen in the frame
  /// of R (d_b = R^T d_ref_b: a body-frame perturbation against a world-frame one) and whose
  /// other blocks are the reference's: R on those blocks of J_ref_this, R^T on J_this_ref's.
  template <std::size_t N>
  static bool RefThisRotated(Mat15& J, const Mat3& R,
                             const std::array<Block, N>& rotated) noexcept {
    Permutation(J, Ref::order, Order, {});
    for (const Block b : rotated) RefThisBlock(J, b, b) = R;
    return true;
  }
  template <std::size_t N>
  static bool ThisRefRotated(Mat15& J, const Mat3& R,
                             const std::array<Block, N>& rotated) noexcept {
    Permutation(J, Order, Ref::order, {});
    for (const Block b : rotated) ThisRefBlock(J, b, b) = R.transpose();
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
      const double sign = (b == Block::bg || b == Block::ba) ? BiasSign : 1;
      J.template block<3, 3>(rows.offset(b), cols.offset(b)).diagonal().setConstant(sign);
    }
    for (const BlockMap& m : blocks)
      J.template block<3, 3>(rows.offset(m.first), cols.offset(m.first)) = m.second;
  }
};

/// A state convention with additive biases, b = b^ + db (all but exotic ones).
template <const BlockOrder& Order>
class StateChart : public ConventionChart<ImuState, Order, 1> {
 protected:
  using Base = ConventionChart<ImuState, Order, 1>;
  static void RetractBiases(const ImuState& x, const Vec15& d, ImuState& y) noexcept {
    y.bg = x.bg + d.template segment<3>(Base::bg);
    y.ba = x.ba + d.template segment<3>(Base::ba);
  }
  static void LocalBiases(const ImuState& x, const ImuState& y, Vec15& d) noexcept {
    d.template segment<3>(Base::bg) = y.bg - x.bg;
    d.template segment<3>(Base::ba) = y.ba - x.ba;
  }
};

/// An increment convention; its bias entry is Delta b = Delta b^ + BiasSign db. (Negation
/// is exact, so x + (-1) d and x - d are the same double, as are -(y - x) and x - y.)
template <const BlockOrder& Order, int BiasSign>
class IncrementChart : public ConventionChart<PreintIncrement, Order, BiasSign> {
 protected:
  using Base = ConventionChart<PreintIncrement, Order, BiasSign>;
  static constexpr double kSign = BiasSign;
  static void RetractBiases(const PreintIncrement& x, const Vec15& d, PreintIncrement& y) noexcept {
    y.dbg = x.dbg + kSign * d.template segment<3>(Base::bg);
    y.dba = x.dba + kSign * d.template segment<3>(Base::ba);
  }
  static void LocalBiases(const PreintIncrement& x, const PreintIncrement& y, Vec15& d) noexcept {
    d.template segment<3>(Base::bg) = kSign * (y.dbg - x.dbg);
    d.template segment<3>(Base::ba) = kSign * (y.dba - x.dba);
  }
};

/// Which side of the estimate an increment chart's rotation error multiplies.
enum class RotationErrorSide {
  kRight,  ///< Delta R = Delta R^ Exp(dtheta): the reference's perturbation
  kLeft,   ///< Delta R = Exp(dtheta) Delta R^, in the interval's start frame
};

/// An increment chart with additive dp, dv, the rotation error on `Side`, in a block order and
/// bias sign. On the right (the reference's perturbations) its Jacobians to and from the
/// reference are the permutation with that sign, both ways. On the left, against the
/// reference, Exp(dtheta) Delta R^ = Delta R^ Exp(Delta R^T dtheta), so dtheta_ref =
/// Delta R^T dtheta and dtheta = Delta R^ dtheta_ref, the other blocks a permutation (Basalt's
/// delta state and OKVIS2's P_delta are that chart; each plugin names it after its system).
/// Declared with a `using` of RightPerturbedIncrementChart or LeftPerturbedIncrementChart (a
/// template's comma cannot stand in the IMUCONV_PLUGIN line).
template <const BlockOrder& Order, int BiasSign, RotationErrorSide Side>
class PerturbedIncrementChart : public IncrementChart<Order, BiasSign> {
  using Base = IncrementChart<Order, BiasSign>;
  static constexpr bool kLeft = Side == RotationErrorSide::kLeft;

 public:
  void retract(const PreintIncrement& x, const Vec15& d,
               PreintIncrement& y) const noexcept override {
    if constexpr (kLeft)
      y.dR = so3::Exp(d.template segment<3>(Base::theta)) * x.dR;
    else
      y.dR = x.dR * so3::Exp(d.template segment<3>(Base::theta));
    y.dp = x.dp + d.template segment<3>(Base::p);
    y.dv = x.dv + d.template segment<3>(Base::v);
    Base::RetractBiases(x, d, y);
  }
  void local(const PreintIncrement& x, const PreintIncrement& y, Vec15& d) const noexcept override {
    if constexpr (kLeft)
      d.template segment<3>(Base::theta) = so3::Log(y.dR * x.dR.transpose());
    else
      d.template segment<3>(Base::theta) = so3::Log(x.dR.transpose() * y.dR);
    d.template segment<3>(Base::p) = y.dp - x.dp;
    d.template segment<3>(Base::v) = y.dv - x.dv;
    Base::LocalBiases(x, y, d);
  }
  bool J_ref_this(const PreintIncrement& x, Mat15& J) const noexcept override {
    if constexpr (kLeft) return Base::RefThis(J, {{Block::theta, x.dR.transpose()}});
    (void)x;
    return Base::RefThis(J, {});
  }
  bool J_this_ref(const PreintIncrement& x, Mat15& J) const noexcept override {
    if constexpr (kLeft) return Base::ThisRef(J, {{Block::theta, x.dR}});
    (void)x;
    return Base::ThisRef(J, {});
  }
};

template <const BlockOrder& Order, int BiasSign>
using RightPerturbedIncrementChart =
    PerturbedIncrementChart<Order, BiasSign, RotationErrorSide::kRight>;
template <const BlockOrder& Order, int BiasSign>
using LeftPerturbedIncrementChart =
    PerturbedIncrementChart<Order, BiasSign, RotationErrorSide::kLeft>;

/// The state reference chart `left` (p + dp, Exp(dtheta) R, v + dv, b + db, order
/// [p, theta, v, bg, ba]) applied to an increment: the chart of Basalt's delta state and of
/// OKVIS2's P_delta, which their plugins register under their systems' names.
using LeftReferenceIncrementChart = LeftPerturbedIncrementChart<kLeftOrder, 1>;

/// The rotation a chart's body frame is that of: the state's R, or the increment's Delta R.
inline const Mat3& RotationOf(const ImuState& x) noexcept { return x.R; }
inline const Mat3& RotationOf(const PreintIncrement& x) noexcept { return x.dR; }
inline Mat3& RotationOf(ImuState& x) noexcept { return x.R; }
inline Mat3& RotationOf(PreintIncrement& x) noexcept { return x.dR; }

/// A chart (Chart, a StateChart or IncrementChart) whose blocks `Rotated` are the reference
/// chart's seen in the frame of the estimate's rotation (d_b = R^T d_ref_b, at least to first
/// order) and whose other blocks are the reference's: its Jacobians follow from that list,
/// so the plugin writes only retract and local.
template <class ChartBase, const auto& Rotated>
class RotatedBlocksChart : public ChartBase {
 public:
  using Value = typename ChartBase::value_type;
  bool J_ref_this(const Value& x, Mat15& J) const noexcept override {
    return ChartBase::RefThisRotated(J, RotationOf(x), Rotated);
  }
  bool J_this_ref(const Value& x, Mat15& J) const noexcept override {
    return ChartBase::ThisRefRotated(J, RotationOf(x), Rotated);
  }
};

/// The translation block B (p or v) of a state (p, v) or an increment (dp, dv), const or not.
template <Block B, class Value>
auto& TranslationOf(Value& x) noexcept {
  static_assert(B == Block::p || B == Block::v, "a translation block");
  if constexpr (std::is_same_v<std::remove_const_t<Value>, ImuState>) {
    if constexpr (B == Block::p)
      return x.p;
    else
      return x.v;
  } else {
    if constexpr (B == Block::p)
      return x.dp;
    else
      return x.dv;
  }
}

/// Whether `blocks` names `b`.
template <std::size_t N>
constexpr bool Contains(const std::array<Block, N>& blocks, Block b) noexcept {
  for (const Block c : blocks)
    if (c == b) return true;
  return false;
}

/// A chart with the rotation perturbed on the right, R = R^ Exp(dtheta), each translation
/// block t (p, v) in the body frame of the estimate, t = t^ + R^ dt, when it is one of
/// `Rotated` and additive, t = t^ + dt, when it is not, and the biases of ChartBase: Forster's
/// state, gtsam::NavState's, GTSAM ManifoldPreintegration's increment. One list gives retract,
/// local and (RotatedBlocksChart) the Jacobians. Against `left` a right rotation error is the
/// left one seen in the body frame, against `preint_reference` it is that chart's own: theta is
/// in `Rotated` for a state chart and only there (checked).
template <class ChartBase, const auto& Rotated>
class RightRotationChart : public RotatedBlocksChart<ChartBase, Rotated> {
  using Value = typename ChartBase::value_type;
  static_assert(Contains(Rotated, Block::theta) == std::is_same_v<Value, ImuState>,
                "theta is a body-frame block against `left`, the reference's own against "
                "`preint_reference`");

 public:
  void retract(const Value& x, const Vec15& d, Value& y) const noexcept override {
    RotationOf(y) = RotationOf(x) * so3::Exp(d.template segment<3>(ChartBase::theta));
    Translate<Block::p>(x, d, y);
    Translate<Block::v>(x, d, y);
    ChartBase::RetractBiases(x, d, y);
  }
  void local(const Value& x, const Value& y, Vec15& d) const noexcept override {
    const Mat3 Rt = RotationOf(x).transpose();
    d.template segment<3>(ChartBase::theta) = so3::Log(Rt * RotationOf(y));
    Difference<Block::p>(Rt, x, y, d);
    Difference<Block::v>(Rt, x, y, d);
    ChartBase::LocalBiases(x, y, d);
  }

 private:
  static constexpr int OffsetOf(Block b) noexcept {
    return b == Block::p ? ChartBase::p : ChartBase::v;
  }
  template <Block B>
  static void Translate(const Value& x, const Vec15& d, Value& y) noexcept {
    if constexpr (Contains(Rotated, B))
      TranslationOf<B>(y) =
          TranslationOf<B>(x) + RotationOf(x) * d.template segment<3>(OffsetOf(B));
    else
      TranslationOf<B>(y) = TranslationOf<B>(x) + d.template segment<3>(OffsetOf(B));
  }
  template <Block B>
  static void Difference(const Mat3& Rt, const Value& x, const Value& y, Vec15& d) noexcept {
    if constexpr (Contains(Rotated, B))
      d.template segment<3>(OffsetOf(B)) = Rt * (TranslationOf<B>(y) - TranslationOf<B>(x));
    else
      d.template segment<3>(OffsetOf(B)) = TranslationOf<B>(y) - TranslationOf<B>(x);
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
