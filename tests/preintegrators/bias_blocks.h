// A preintegrator's 9x6 bias Jacobian against central differences of its re-integration,
// block by block: shared by the tests of the schemes whose kernels expose their own state.
#pragma once

#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "imuconv/preintegrator.h"
#include "scale_aware.h"

namespace imuconv::test {

using Mat96 = Eigen::Matrix<double, 9, 6>;

/// Central differences (step h) of `error_at(input)`, a re-integration's 9-vector error in the
/// scheme's chart against its nominal, with respect to the six bias components, columns in
/// the order [bg, ba] or, with `accel_first`, [ba, bg].
template <class ErrorAt>
Mat96 BiasCentralDifferences(const PreintegrationInput& in, bool accel_first, double h,
                             ErrorAt error_at) {
  Mat96 numeric;
  for (int c = 0; c < 6; ++c) {
    Vec9 side[2];
    for (int s = 0; s < 2; ++s) {
      PreintegrationInput moved = in;
      Vec3& a = accel_first ? moved.ba : moved.bg;
      Vec3& b = accel_first ? moved.bg : moved.ba;
      (c < 3 ? a[c] : b[c - 3]) += (s == 0 ? h : -h);
      side[s] = error_at(moved);
    }
    numeric.col(c) = (side[0] - side[1]) / (2 * h);
  }
  return numeric;
}

/// Each 3x3 block's relative difference |A_b - N_b| / |N_b|, printed under `label` with the
/// block's name, must be at most bound(column block); a block the differences find zero must
/// be zero.
template <class Bound>
void ExpectBiasBlocks(const std::string& label, const Mat96& analytic, const Mat96& numeric,
                      const char* const (&rows)[3], const char* const (&cols)[2], Bound bound) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 2; ++j) {
      if (numeric.block<3, 3>(3 * i, 3 * j).norm() == 0.0) {
        EXPECT_EQ((analytic.block<3, 3>(3 * i, 3 * j).norm()), 0.0)
            << label << " d" << rows[i] << "/d" << cols[j];
        continue;
      }
      const double d = BlockRelativeDiff(numeric, analytic, i, j);
      std::printf("[ J_bias  ] %-30s d%s/d%s %.2g\n", label.c_str(), rows[i], cols[j], d);
      EXPECT_LE(d, bound(j)) << label << " d" << rows[i] << "/d" << cols[j];
    }
}

}  // namespace imuconv::test
