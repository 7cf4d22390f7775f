// Did-you-mean: the known names closest to a mistyped one, for every "unknown ..." message
// (the registry's unknown plugin id, the pipeline's id checks, the command line's subcommands
// and flags). One helper, so a typo gets the same suggestion wherever it is made.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "imuconv/export.h"

namespace imuconv {

/// Edit distance between `a` and `b` compared without case (ASCII): insertions, deletions,
/// substitutions and transpositions of two adjacent characters each cost 1 (the optimal string
/// alignment distance), so "chek"/"check", "trails"/"trials" and "gtsam_NavState"/"gtsam_navstate"
/// are at distance 1, 1 and 0. Bounded work: strings longer than 256 characters are not
/// compared (the distance is then reported as their length difference plus 256).
IMUCONV_API std::size_t EditDistance(std::string_view a, std::string_view b);

/// The known names a typo of `word` most plausibly was: those at the smallest edit distance,
/// when that distance is at most |word| / 4 clamped to [1, 3] (one slip in a short name, two in
/// a long one, never more than three: more would suggest names that merely share letters), in
/// the order of `known`. Empty when `word` is itself known (exactly), longer than 256
/// characters, or nothing is close enough.
IMUCONV_API std::vector<std::string> ClosestNames(std::string_view word,
                                                  const std::vector<std::string>& known);

/// " (did you mean 'a'?)" or " (did you mean 'a' or 'b'?)" for ClosestNames(word, known); "" when
/// there is no suggestion. The names are quoted with Printable's escaping.
[[nodiscard]] IMUCONV_API std::string DidYouMean(std::string_view word,
                                                 const std::vector<std::string>& known);

}  // namespace imuconv
