// An enumeration's names written once, as a table in the order of its values, and read by one
// bounds-checked lookup. The check is the point: an enum that came through a plugin, a file or
// a cast can hold a value that is none of its enumerators, and such a value must name nothing
// (the caller's `outside`) rather than read past the table.
#pragma once

#include <cstddef>

namespace imuconv {

/// names[value - first], where `names` lists the enum's names from its value `first` on, one
/// per consecutive value; `outside` for a value the table does not cover.
template <class Enum, std::size_t N>
constexpr const char* EnumName(Enum value, Enum first, const char* const (&names)[N],
                               const char* outside) noexcept {
  const long long i = static_cast<long long>(value) - static_cast<long long>(first);
  return (i >= 0 && i < static_cast<long long>(N)) ? names[i] : outside;
}

}  // namespace imuconv
