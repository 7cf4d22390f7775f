// What the result-array collector (array_collector.h) keeps of the output document while it
// reads it: the frames it is in, where each key's values go (the key with the indices of
// arrays of objects removed, the pointer with them kept), and per key the occurrences and values
// that decide at the end whether they fill one N-d array. Internal to imuconv_pipeline; the
// rule is stated in imuconv/pipeline/result_arrays.h.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <deque>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "imuconv/pipeline/result_arrays.h"

namespace imuconv::pipeline::detail {

using ojson = nlohmann::ordered_json;

/// The deepest nesting of objects and arrays read.
constexpr std::size_t kMaxDepth = 256;

/// |i| <= 2^53: every such integer is a double exactly.
constexpr std::int64_t kExactInDouble = std::int64_t{1} << 53;

/// A member name as a JSON pointer segment (RFC 6901: '~' -> "~0", '/' -> "~1").
inline std::string Escape(const std::string& s) {
  if (s.find_first_of("~/") == std::string::npos) return s;  // nearly every name
  std::string e;
  for (char c : s)
    e += c == '~' ? std::string("~0") : c == '/' ? std::string("~1") : std::string(1, c);
  return e;
}

inline std::string Join(const std::string& prefix, const std::string& segment) {
  return prefix.empty() ? segment : prefix + "/" + segment;
}

/// A member name met in the objects of one frame key, resolved once: its escaped name, the key
/// of its values and, once known, their entries in the collector's lists (elements of an array
/// of objects repeat their members, so each value after the first finds these here instead of
/// joining and hashing its key).
struct MemberSlot {
  std::string name;     ///< as read
  std::string escaped;  ///< as a pointer segment
  std::string key;      ///< the frame key joined with it
  int child_key =
      -1;  ///< the entry of `key` in the collector's frame keys, once an object or array is there
  int numeric = -1;  ///< its entry in the collector's numeric keys, once known
  int value = -1;    ///< and in its sidecar keys
};
/// A frame key (objects and arrays of objects with one key share it) and the members met under it,
/// in the order first met. A deque: slots are held by address while more are added.
struct FrameKey {
  std::string key;
  std::deque<MemberSlot> members;
};

/// Where a value goes: the current member of the innermost frame (`slot`; its key and pointer
/// are derived only when needed), or, with no slot, the key and pointer given.
struct Destination {
  MemberSlot* slot = nullptr;
  std::string key, pointer;
};

struct Frame {
  bool aoo = false;              ///< an array of objects; else an object
  std::string key;               ///< the frame's key (indices of arrays of objects removed)
  std::string pointer;           ///< its pointer, indices kept, without the leading '/'
  int key_id = -1;               ///< the frame key's entry in the collector's list of them
  MemberSlot* member = nullptr;  ///< object: the current member
  std::size_t count = 0;         ///< object: members so far; array: elements so far
  bool element = false;  ///< an object that is an element of an array of objects (not /tasks)
  bool task = false, named = false;  ///< an element of /tasks, and whether its name was read
  bool tasks = false;                ///< the /tasks array: elements named, not stacked
  int aoo_id = -1;                   ///< an array of objects' entry in the collector's list of them
};
/// What is known of an array of objects, by key: how many instances (one per element of the
/// enclosing array of objects, when it is present in each), and their common length.
struct ArrayOfObjects {
  std::string key;
  int parent;
  std::size_t instances = 0, length = 0;
  bool ragged = false;
};
/// Where a key was found: the arrays of objects above it and, per value, their indices.
struct Occurrences {
  std::string key;
  std::vector<int> levels;
  std::vector<std::uint32_t> indices;  ///< levels.size() per value
  std::size_t count = 0;
};
struct NumericKey : Occurrences {
  NdArray::Type type = NdArray::Type::kInt64;
  std::vector<double> data;
  std::vector<std::int64_t> integers;
  std::vector<std::vector<std::size_t>> shapes;  ///< the distinct shapes of its values
  std::vector<std::uint32_t> shape_of;           ///< per value
  std::vector<std::size_t> offset;               ///< per value, into data / integers

  /// The n numbers of the value just recorded, of `shape`: the doubles at `reals` (possibly
  /// unaligned), or `values` when !real.
  /// A key is int64 until its first real; then its integers so far become reals, each by
  /// to_real (which refuses one that is not exact in a double).
  template <class ToReal>
  void Append(const std::vector<std::size_t>& shape, const void* reals, const std::int64_t* values,
              std::size_t n, bool real, const ToReal& to_real) {
    if (real && type == NdArray::Type::kInt64) {
      data.reserve(integers.size() + n);
      for (std::int64_t i : integers) data.push_back(to_real(i));
      integers = {};
      type = NdArray::Type::kFloat64;
    }
    const auto s = std::find(shapes.begin(), shapes.end(), shape);
    shape_of.push_back(static_cast<std::uint32_t>(s - shapes.begin()));
    if (s == shapes.end()) shapes.push_back(shape);
    if (type == NdArray::Type::kFloat64) {
      offset.push_back(data.size());
      if (real) {
        data.resize(data.size() + n);
        std::memcpy(data.data() + data.size() - n, reals, n * sizeof(double));
      } else {
        for (std::size_t i = 0; i < n; ++i) data.push_back(to_real(values[i]));
      }
    } else {
      offset.push_back(integers.size());
      for (std::size_t i = 0; i < n; ++i) integers.push_back(values[i]);  // (few: indices, counts)
    }
  }
};
struct ValueKey : Occurrences {
  ojson first;
  std::vector<std::pair<std::size_t, ojson>> other;  ///< values that differ from the first

  /// The value just recorded (count includes it): the first is kept, a later one only where
  /// it differs from the first.
  void Keep(ojson v) {
    if (count == 1)
      first = std::move(v);
    else if (v != first)
      other.emplace_back(count - 1, std::move(v));
  }
};

}  // namespace imuconv::pipeline::detail
