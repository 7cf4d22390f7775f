// The state block and the ambient Jacobians of the reference chart `left`
// (reference_charts.h: p = p^ + dp, R = Exp(dtheta) R^, v, b additive; order [p, theta, v, bg,
// ba], which is the block's order with theta in place of the quaternion).
#include "imuconv/ceres/state_block.h"

#include <Eigen/Geometry>

#include "imuconv/reference_charts.h"
#include "imuconv/so3.h"

namespace imuconv::ceres_factors {

// The Jacobians below are written for the left chart's order [p, theta, v, bg, ba].
static_assert(left_idx::p == 0 && left_idx::theta == 3 && left_idx::v == 6 && left_idx::bg == 9 &&
              left_idx::ba == 12);
static_assert(block_idx::p == 0 && block_idx::q == 3 && block_idx::v == 7 && block_idx::bg == 10 &&
              block_idx::ba == 13);

void ToStateBlock(const ImuState& x, double* block) {
  Eigen::Quaterniond q(x.R);
  q.normalize();
  if (q.w() < 0.0) q.coeffs() = -q.coeffs();
  const auto put = [block](int offset, const Vec3& a) {
    for (int i = 0; i < 3; ++i) block[offset + i] = a[i];
  };
  put(block_idx::p, x.p);
  block[block_idx::q + 0] = q.w();
  block[block_idx::q + 1] = q.x();
  block[block_idx::q + 2] = q.y();
  block[block_idx::q + 3] = q.z();
  put(block_idx::v, x.v);
  put(block_idx::bg, x.bg);
  put(block_idx::ba, x.ba);
}

ImuState FromStateBlock(const double* block) {
  ImuState x;
  Eigen::Quaterniond q(block[block_idx::q + 0], block[block_idx::q + 1], block[block_idx::q + 2],
                       block[block_idx::q + 3]);
  q.normalize();
  x.R = q.toRotationMatrix();
  x.p = Eigen::Map<const Vec3>(block + block_idx::p);
  x.v = Eigen::Map<const Vec3>(block + block_idx::v);
  x.bg = Eigen::Map<const Vec3>(block + block_idx::bg);
  x.ba = Eigen::Map<const Vec3>(block + block_idx::ba);
  return x;
}

namespace {
// The block's unit quaternion, (w, u).
double UnitW(const double* block, Vec3& u) {
  Eigen::Vector4d q(block[block_idx::q], block[block_idx::q + 1], block[block_idx::q + 2],
                    block[block_idx::q + 3]);
  q.normalize();
  u = q.tail<3>();
  return q[0];
}
}  // namespace

// Rotation part: the left chart's theta of y = FromStateBlock(block + dq) is Log(R_y R_x^T), the
// vector part of q_y (x) q_x^* doubled to first order. FromStateBlock normalizes, which removes
// the component of dq along q; (q (x) q^*) has no vector part, so the normalization leaves the
// first order unchanged: dtheta = 2 vec(dq (x) q^*) = 2 [-u | w I + [u]x] dq (dq = (dw, du)).
Eigen::Matrix<double, 15, 16, Eigen::RowMajor> LeftMinusJacobian(const double* block) {
  Vec3 u;
  const double w = UnitW(block, u);
  Eigen::Matrix<double, 15, 16, Eigen::RowMajor> M;
  M.setZero();
  M.block<3, 3>(0, block_idx::p).setIdentity();
  M.block<3, 1>(3, block_idx::q) = -2.0 * u;
  M.block<3, 3>(3, block_idx::q + 1) = 2.0 * (w * Mat3::Identity() + so3::skew(u));
  M.block<3, 3>(6, block_idx::v).setIdentity();
  M.block<3, 3>(9, block_idx::bg).setIdentity();
  M.block<3, 3>(12, block_idx::ba).setIdentity();
  return M;
}

// Rotation part: q(Exp(dtheta) R) = (1, dtheta/2) (x) q to first order, i.e.
// dq = 1/2 (0, dtheta) (x) (w, u) = 1/2 [-u^T ; w I - [u]x] dtheta. With the block above,
// M P = u u^T + (w I + [u]x)(w I - [u]x) = (w^2 + |u|^2) I = I.
Eigen::Matrix<double, 16, 15, Eigen::RowMajor> LeftPlusJacobian(const double* block) {
  Vec3 u;
  const double w = UnitW(block, u);
  Eigen::Matrix<double, 16, 15, Eigen::RowMajor> P;
  P.setZero();
  P.block<3, 3>(block_idx::p, 0).setIdentity();
  P.block<1, 3>(block_idx::q, 3) = -0.5 * u.transpose();
  P.block<3, 3>(block_idx::q + 1, 3) = 0.5 * (w * Mat3::Identity() - so3::skew(u));
  P.block<3, 3>(block_idx::v, 6).setIdentity();
  P.block<3, 3>(block_idx::bg, 9).setIdentity();
  P.block<3, 3>(block_idx::ba, 12).setIdentity();
  return P;
}

void LeftToAmbient(const Eigen::Ref<const Eigen::MatrixXd>& H, const double* block,
                   double* ambient) {
  Vec3 u;
  const double w = UnitW(block, u);
  Eigen::Matrix<double, 3, 4> Mq;  // the rotation rows of M_left, its quaternion columns
  Mq.col(0) = -2.0 * u;
  Mq.rightCols<3>() = 2.0 * (w * Mat3::Identity() + so3::skew(u));
  const Eigen::Index rows = H.rows();
  Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, kStateBlockSize, Eigen::RowMajor>> J(ambient,
                                                                                        rows, 16);
  J.leftCols<3>() = H.middleCols<3>(0);                     // p
  J.middleCols<4>(block_idx::q) = H.middleCols<3>(3) * Mq;  // theta
  J.rightCols<9>() = H.rightCols<9>();                      // v, bg, ba
}

}  // namespace imuconv::ceres_factors
