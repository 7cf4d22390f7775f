// One anchor writer of `imuconv refcase --anchor NAME` (anchor.h): a system's computed fields
// of tests/data/reference/anchors/NAME/, from a case, with that system's input conventions.
// Each system's writer is one file in this folder, ending with IMUCONV_ANCHOR_WRITER; CMake
// lists the folder's files into the table anchor.cpp reads (anchor_table.inc), so adding a
// system adds a file here and edits none.
#pragma once

#include <Eigen/Geometry>
#include <boost/preprocessor/seq/for_each.hpp>
#include <boost/preprocessor/stringize.hpp>
#include <boost/preprocessor/tuple/elem.hpp>
#include <nlohmann/json.hpp>
#include <string>
#include <type_traits>

#include "imuconv/registry.h"
#include "imuconv/so3.h"
#include "imuconv/window.h"
#include "refcase.h"

namespace imuconv::refcase {

struct AnchorWriter {
  const char* name;  ///< the NAME of --anchor and of the anchors' folder
  nlohmann::json (*write)(const Registry& reg, const Case& k);
};

namespace anchor_support {

/// The whole case, first sample to last, at the bias estimate given.
inline PreintegrationInput Input(const Case& k, const Vec3& bg, const Vec3& ba) {
  PreintegrationInput in;
  const Status st = MakeWindow(k.samples.data(), k.samples.size(), k.samples.front().t,
                               k.samples.back().t, in.window);
  if (!st.ok()) throw Error("/imu: " + st.message());
  in.bg = bg;
  in.ba = ba;
  in.noise = k.noise;
  return in;
}

inline void Require(const Status& st, const char* what) {
  if (!st.ok()) throw Error(std::string(what) + ": " + st.message());
}

inline nlohmann::json Wxyz(const Eigen::Quaterniond& q) {
  return nlohmann::json::array({q.w(), q.x(), q.y(), q.z()});
}

/// The case's start rotation from its quaternion as written (Case::q_s_wxyz: sign kept, not
/// normalised), the way the systems' frames hold it; a system whose constructor normalises
/// (Sophus, MTK's SO3) calls .normalized() on it.
inline Eigen::Quaterniond StartQuaternion(const Case& k) {
  return Eigen::Quaterniond(k.q_s_wxyz[0], k.q_s_wxyz[1], k.q_s_wxyz[2], k.q_s_wxyz[3]);
}

/// The rotation Exp(dtheta) as a quaternion with w >= 0.
inline Eigen::Quaterniond QuaternionExp(const Vec3& dtheta) {
  const Eigen::Vector4d q = so3::ToQuaternionWxyz(so3::Exp(dtheta));
  return Eigen::Quaterniond(q[0], q[1], q[2], q[3]);
}

/// A field as the anchor files write it: a column vector as an array, a matrix as an array of
/// rows (ToJsonVec, ToJson), a number as itself.
template <typename Derived>
nlohmann::json FieldJson(const Eigen::MatrixBase<Derived>& m) {
  if constexpr (Derived::ColsAtCompileTime == 1)
    return ToJsonVec(m);
  else
    return ToJson(m);
}
template <typename T, std::enable_if_t<std::is_arithmetic_v<T>, int> = 0>
nlohmann::json FieldJson(T x) {
  return x;
}

}  // namespace anchor_support
}  // namespace imuconv::refcase

#define IMUCONV_ANCHOR_MEMBER_ENTRY(r, of_obj, member) \
  {BOOST_PP_STRINGIZE(member),                         \
   BOOST_PP_TUPLE_ELEM(2, 0, of_obj)(BOOST_PP_TUPLE_ELEM(2, 1, of_obj).member)},
/// The entries {"member", OF(OBJ.member)} of a JSON object, each followed by a comma, for each
/// member of MEMBERS, a Boost.Preprocessor sequence (a)(b)(c): where an anchor file names a
/// field as the system's struct names its member, the name is written once (OF: FieldJson, or
/// the system's own conversion).
#define IMUCONV_ANCHOR_MEMBERS(OF, OBJ, MEMBERS) \
  BOOST_PP_SEQ_FOR_EACH(IMUCONV_ANCHOR_MEMBER_ENTRY, (OF, OBJ), MEMBERS)

/// Declares this file's writer: STEM is the file's name without .cpp, NAME the --anchor name,
/// WRITE the function json(const Registry&, const Case&).
#define IMUCONV_ANCHOR_WRITER(STEM, NAME, WRITE)   \
  namespace imuconv::refcase {                     \
  const AnchorWriter& STEM##_anchor_writer() {     \
    static const AnchorWriter writer{NAME, WRITE}; \
    return writer;                                 \
  }                                                \
  }
