#include "imuconv/did_you_mean.h"

#include <algorithm>
#include <limits>

#include "imuconv/printable.h"

namespace imuconv {

namespace {

constexpr std::size_t kLongestCompared = 256;  // hostile names cost O(n*m): bounded here
constexpr std::size_t kMostSlips = 3;          // beyond, a "suggestion" merely shares letters

char Fold(char c) { return c >= 'A' && c <= 'Z' ? static_cast<char>(c - 'A' + 'a') : c; }

}  // namespace

std::size_t EditDistance(std::string_view a, std::string_view b) {
  const std::size_t n = a.size(), m = b.size();
  if (n > kLongestCompared || m > kLongestCompared)
    return (n > m ? n - m : m - n) + kLongestCompared;
  // Three rows of the dynamic programme: the transposition looks two rows back.
  std::vector<std::size_t> prev2(m + 1), prev(m + 1), row(m + 1);
  for (std::size_t j = 0; j <= m; ++j) prev[j] = j;
  for (std::size_t i = 1; i <= n; ++i) {
    row[0] = i;
    for (std::size_t j = 1; j <= m; ++j) {
      const bool same = Fold(a[i - 1]) == Fold(b[j - 1]);
      std::size_t d = std::min({prev[j] + 1, row[j - 1] + 1, prev[j - 1] + (same ? 0 : 1)});
      if (i > 1 && j > 1 && Fold(a[i - 1]) == Fold(b[j - 2]) && Fold(a[i - 2]) == Fold(b[j - 1]))
        d = std::min(d, prev2[j - 2] + 1);
      row[j] = d;
    }
    std::swap(prev2, prev);
    std::swap(prev, row);
  }
  return prev[m];
}

std::vector<std::string> ClosestNames(std::string_view word,
                                      const std::vector<std::string>& known) {
  if (word.size() > kLongestCompared || std::find(known.begin(), known.end(), word) != known.end())
    return {};
  const std::size_t allowed = std::clamp<std::size_t>(word.size() / 4, 1, kMostSlips);
  std::size_t best = std::numeric_limits<std::size_t>::max();
  std::vector<std::string> out;
  for (const auto& k : known) {
    const std::size_t d = EditDistance(word, k);
    if (d > allowed || d > best) continue;
    if (d < best) out.clear();
    best = d;
    if (std::find(out.begin(), out.end(), k) == out.end()) out.push_back(k);
  }
  return out;
}

std::string DidYouMean(std::string_view word, const std::vector<std::string>& known) {
  const std::vector<std::string> names = ClosestNames(word, known);
  if (names.empty()) return "";
  std::string s = " (did you mean ";
  for (std::size_t i = 0; i < names.size(); ++i)
    s += (i == 0 ? "" : i + 1 == names.size() ? " or " : ", ") + Quoted(names[i]);
  return s + "?)";
}

}  // namespace imuconv
