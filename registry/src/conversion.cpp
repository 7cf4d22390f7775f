#include "imuconv/conversion.h"

#include <cstring>
#include <string>

#include "imuconv/numeric.h"
#include "imuconv/printable.h"
#include "imuconv/reference_charts.h"
#include "imuconv/registry.h"
#include "numeric_jacobian.h"

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
        if (maskB[k] >> j & 1u)
          C.block<3, 3>(3 * i, 3 * j).noalias() +=
              A.block<3, 3>(3 * i, 3 * k) * B.block<3, 3>(3 * k, 3 * j);
    }
  return C;
}

}  // namespace

template <class Value>
Mat15 ToReference(const Chart<Value>& c, const Value& x) {
  Mat15 J;
  if (c.J_ref_this(x, J)) return J;
  return detail::NumericJacobian(c, ReferenceChart<Value>{}, x);
}

template <class Value>
Mat15 FromReference(const Chart<Value>& c, const Value& x) {
  Mat15 J;
  if (c.J_this_ref(x, J)) return J;
  return detail::NumericJacobian(ReferenceChart<Value>{}, c, x);
}

template <class Value>
Mat15 Conversion(const Chart<Value>& from, const Chart<Value>& to, const Value& x) {
  if (SameId(from.id(), to.id())) return Mat15::Identity();
  return BlockSparseProduct(FromReference(to, x), ToReference(from, x));
}

template <class Value>
Mat15 ConvertCovariance(const Chart<Value>& from, const Chart<Value>& to, const Value& x,
                        const Mat15& S) {
  const Mat15 J = Conversion(from, to, x);
  Mat15 out = J * S * J.transpose();
  return 0.5 * (out + out.transpose());
}

template <class Value>
Mat15 ConvertTransition(const Chart<Value>& from, const Chart<Value>& to, const Value& x_s,
                        const Value& x_e, const Mat15& Phi) {
  return Conversion(from, to, x_e) * Phi * Conversion(to, from, x_s);
}

IMUCONV_CONVERSION_INSTANCES(, ImuState)
IMUCONV_CONVERSION_INSTANCES(, PreintIncrement)

PropagationResult PropagateIn(const Propagator& prop, const StateConvention& native,
                              const StateConvention& convention, const PropagationInput& in) {
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
