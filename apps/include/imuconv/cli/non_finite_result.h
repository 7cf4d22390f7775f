// The refusal of a matrix that a command computed with an inf or NaN in it. Inputs that pass
// every check can still overflow (a position of 1e200 m squared in J S J^T, or summed with
// others past DBL_MAX in a rotated position): an inf printed in a table, or a null in --json,
// would be a wrong answer given in silence. `imuconv convert` and `imuconv conversion` refuse
// it as a run refuses a non-finite output (io/json_writer.cpp), exit 2.
#pragma once

#include <cmath>
#include <string>
#include <string_view>

#include "imuconv/printable.h"
#include "imuconv/types.h"

namespace imuconv::cli {

/// "" when every entry of `m` is finite; else "COMMAND: the WHAT from 'A' to 'B' produced a
/// non-finite number (row R, column C); nothing is printed: the inputs are too large for
/// double precision (INPUTS)", naming the first such entry (row-major).
[[nodiscard]] inline std::string NonFiniteResultMessage(const Mat15& m, std::string_view command,
                                                        std::string_view what,
                                                        std::string_view from, std::string_view to,
                                                        std::string_view inputs) {
  for (int r = 0; r < 15; ++r)
    for (int c = 0; c < 15; ++c)
      if (!std::isfinite(m(r, c)))
        return std::string(command) + ": the " + std::string(what) + " from " + Quoted(from) +
               " to " + Quoted(to) + " produced a non-finite number (row " + std::to_string(r) +
               ", column " + std::to_string(c) +
               "); nothing is printed: the inputs are too large for double precision (" +
               std::string(inputs) + ")";
  return {};
}

}  // namespace imuconv::cli
