#include "imuconv/conversion.h"

#include <cstring>
#include <string>

#include "imuconv/numeric.h"
#include "imuconv/printable.h"
#include "imuconv/reference_charts.h"
#include "imuconv/registry.h"

namespace imuconv {
namespace {

bool SameId(const char* a, const char* b) { return std::strcmp(a, b) == 0; }

// C = A B for 15x15 matrices made of 3x3 blocks, skipping zero blocks. Conversion Jacobians
// have at most 7 non-zero blocks of 25, so this is several times cheaper than a dense
// product (which Eigen does not vectorise well at this odd size).
Mat15 BlockSparseProduct(const Mat15& A, const Mat15& B) {
  unsigned maskA[5] = {0, 0, 0, 0, 0}, maskB[5] = {0, 0, 0, 0, 0};
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j) {
      if (!A.block<3, 3>(3 * i, 3 * j).isZero(0.0)) maskA[i] |= 1u << j;
      if (!B.block<3, 3>(3 * i, 3 * j).isZero(0.0)) maskB[i] |= 1u << j;
    }
  Mat15 C = Mat15::Zero();
  for (int i = 0; i < 5; ++i)
    for (int k = 0; k < 5; ++k) {
      if (!(maskA[i] >> k & 1u)) continue;
      for (int j = 0; j < 5; ++j)
        if (maskB[k] >> j & 1u) C.block<3, 3>(3 * i, 3 * j).noalias() += A.block<3, 3>(3 * i, 3 * k) * B.block<3, 3>(3 * k, 3 * j);
    }
  return C;
}

// The same four functions for both kinds: Conv's reference chart is RefRetract/RefLocal.
template <typename Conv, typename Value, typename RefLocal>
Mat15 ToReferenceOf(const Conv& c, const Value& x, RefLocal ref_local) {
  Mat15 J;
  if (c.jacobian_to_reference(x, J)) return J;
  return RiddersJacobian([&](const Vec15& d, Vec15& out) {
    Value y;
    c.retract(x, d, y);
    ref_local(x, y, out);
  });
}

template <typename Conv, typename Value, typename RefRetract>
Mat15 FromReferenceOf(const Conv& c, const Value& x, RefRetract ref_retract) {
  Mat15 J;
  if (c.jacobian_from_reference(x, J)) return J;
  return RiddersJacobian([&](const Vec15& e, Vec15& out) {
    Value y;
    ref_retract(x, e, y);
    c.local(x, y, out);
  });
}

}  // namespace

Mat15 ToReference(const ErrorState& c, const ImuState& x) { return ToReferenceOf(c, x, LeftLocal); }
Mat15 ToReference(const PreintConvention& c, const PreintIncrement& x) {
  return ToReferenceOf(c, x, PreintReferenceLocal);
}
Mat15 FromReference(const ErrorState& c, const ImuState& x) { return FromReferenceOf(c, x, LeftRetract); }
Mat15 FromReference(const PreintConvention& c, const PreintIncrement& x) {
  return FromReferenceOf(c, x, PreintReferenceRetract);
}

Mat15 Conversion(const ErrorState& from, const ErrorState& to, const ImuState& x) {
  if (SameId(from.id(), to.id())) return Mat15::Identity();
  return BlockSparseProduct(FromReference(to, x), ToReference(from, x));
}
Mat15 Conversion(const PreintConvention& from, const PreintConvention& to, const PreintIncrement& x) {
  if (SameId(from.id(), to.id())) return Mat15::Identity();
  return BlockSparseProduct(FromReference(to, x), ToReference(from, x));
}

Mat15 ConvertCovariance(const ErrorState& from, const ErrorState& to, const ImuState& x, const Mat15& S) {
  const Mat15 J = Conversion(from, to, x);
  Mat15 out = J * S * J.transpose();
  return 0.5 * (out + out.transpose());
}

Mat15 ConvertTransition(const ErrorState& from, const ErrorState& to, const ImuState& x_s, const ImuState& x_e,
                        const Mat15& Phi) {
  return Conversion(from, to, x_e) * Phi * Conversion(to, from, x_s);
}

PropagationResult PropagateIn(const Propagator& prop, const ErrorState& native, const ErrorState& convention,
                              const PropagationInput& in) {
  PropagationInput nin = in;
  const bool convert = !SameId(convention.id(), native.id());
  if (convert) nin.cov_s = ConvertCovariance(convention, native, in.x_s, in.cov_s);
  PropagationResult r;
  const Status st = prop.propagate(nin, r);
  if (!st.ok()) throw Error("propagator " + Quoted(prop.id()) + ": " + Printable(st.message()));
  if (convert) {
    r.Phi = ConvertTransition(native, convention, in.x_s, r.x_e, r.Phi);
    r.cov = ConvertCovariance(native, convention, r.x_e, r.cov);
  }
  return r;
}

}  // namespace imuconv
