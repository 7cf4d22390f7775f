// Anchor fields named as the kernels name their structs' members: where an anchor file
// (tests/data/reference/anchors) names a field as the kernel's struct names the member, as
// the writers of `imuconv refcase --anchor` do (apps/refcase/anchors/anchor_writer.h), a test
// names each such member once.
#pragma once

#include <boost/preprocessor/seq/for_each.hpp>
#include <boost/preprocessor/stringize.hpp>
#include <boost/preprocessor/tuple/elem.hpp>

#include "imuconv_test.h"

#define IMUCONV_CHECK_ANCHOR_MEMBER(r, check_j_obj, member)                             \
  BOOST_PP_TUPLE_ELEM(3, 0, check_j_obj)                                                \
  (BOOST_PP_STRINGIZE(member), JsonMatrix(BOOST_PP_TUPLE_ELEM(3, 1, check_j_obj).at(    \
                                   BOOST_PP_STRINGIZE(member))),                        \
   BOOST_PP_TUPLE_ELEM(3, 2, check_j_obj).member);
/// CHECK("member", JsonMatrix(J.at("member")), OBJ.member) for each member of MEMBERS, a
/// Boost.Preprocessor sequence (a)(b)(c), in its order. CHECK: one of AnchorFieldDiffs'
/// comparisons (w.Metric, w.Jacobian, ...).
#define IMUCONV_CHECK_ANCHOR_MEMBERS(CHECK, J, OBJ, MEMBERS)                     \
  do {                                                                           \
    BOOST_PP_SEQ_FOR_EACH(IMUCONV_CHECK_ANCHOR_MEMBER, (CHECK, J, OBJ), MEMBERS) \
  } while (0)

#define IMUCONV_READ_ANCHOR_MEMBER(r, read_j_obj, member)        \
  BOOST_PP_TUPLE_ELEM(3, 2, read_j_obj).member =                 \
      BOOST_PP_TUPLE_ELEM(3, 0, read_j_obj)(                     \
          BOOST_PP_TUPLE_ELEM(3, 1, read_j_obj).at(BOOST_PP_STRINGIZE(member)));
/// OBJ.member = READ(J.at("member")) for each member of MEMBERS, a Boost.Preprocessor
/// sequence (a)(b)(c). READ: the field's reader (JsonVec3, ...).
#define IMUCONV_READ_ANCHOR_MEMBERS(READ, J, OBJ, MEMBERS)                     \
  do {                                                                         \
    BOOST_PP_SEQ_FOR_EACH(IMUCONV_READ_ANCHOR_MEMBER, (READ, J, OBJ), MEMBERS) \
  } while (0)
