// The events of one JSON array that is not an array of objects (a vector, a matrix, a list of
// block labels), buffered by the result-array collector (sax_collector.h) while the array is
// read and replayed when it closes: into an N-d array when it is a rectangular array of numbers,
// else into a JSON value for the sidecar. Internal to imuconv_pipeline.
#pragma once

#include <cstddef>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace imuconv::pipeline::detail {

using ojson = nlohmann::ordered_json;

/// The events of an array that is not an array of objects, replayed when it closes.
class ValueBuffer {
 public:
  enum Event : std::uint8_t {
    kBeginArray,
    kEndArray,
    kBeginObject,
    kEndObject,
    kKey,
    kInt,
    kBigUInt,
    kFloat,
    kString,
    kTrue,
    kFalse,
    kNull
  };
  void clear() {
    events.clear();
    ints.clear();
    big.clear();
    floats.clear();
    strings.clear();
  }

  /// The shape when the events are a rectangular array of numbers (numbers at one depth only,
  /// every array at a depth of one length, at least one number); nothing otherwise.
  bool Rectangular(std::vector<std::size_t>& shape) const {
    std::vector<std::size_t>& counts = counts_;  // elements so far of each open array
    std::vector<long long>& dims = dims_;  // each depth's length, -1 until an array there closes
    counts.clear();
    dims.clear();
    std::size_t leaf_depth = 0, max_array_depth = 0;
    const std::size_t n = events.size();
    for (std::size_t i = 0; i < n; ++i) {
      switch (events[i]) {
        case kBeginArray:
          if (!counts.empty()) ++counts.back();
          max_array_depth = std::max(max_array_depth, counts.size());
          counts.push_back(0);
          if (dims.size() < counts.size()) dims.push_back(-1);
          break;
        case kEndArray: {
          const long long c = static_cast<long long>(counts.back());
          counts.pop_back();
          long long& d = dims[counts.size()];
          if (d >= 0 && d != c) return false;
          d = c;
          break;
        }
        case kInt:
        case kFloat: {
          // A run of numbers (a vector, a matrix row) is at one depth: counted at once.
          std::size_t end = i + 1;
          while (end < n && (events[end] == kFloat || events[end] == kInt)) ++end;
          counts.back() += end - i;
          i = end - 1;
          if (leaf_depth == 0)
            leaf_depth = counts.size();
          else if (leaf_depth != counts.size())
            return false;
          break;
        }
        default:
          return false;
      }
    }
    if (leaf_depth == 0 || max_array_depth >= leaf_depth) return false;
    shape.assign(dims.begin(), dims.begin() + static_cast<std::ptrdiff_t>(leaf_depth));
    return true;
  }

  /// Whether `o` holds the same events and values. Numbers compare with ==, as JSON values do
  /// (0.0 equals -0.0, NaN equals nothing), so that equal buffers give equal JSON values.
  bool SameEvents(const ValueBuffer& o) const {
    return events == o.events && ints == o.ints && big == o.big && floats == o.floats &&
           strings == o.strings;
  }

  /// The events as a JSON value (numbers as they were read: integers stay integers).
  ojson ToJson() const {
    ojson root;
    std::vector<ojson*> open;
    std::string key;
    std::size_t i_int = 0, i_big = 0, i_float = 0, i_string = 0;
    auto place = [&](ojson v) -> ojson* {
      if (open.empty()) {
        root = std::move(v);
        return &root;
      }
      ojson& parent = *open.back();
      if (parent.is_array()) {
        parent.push_back(std::move(v));
        return &parent.back();
      }
      parent[key] = std::move(v);
      return &parent[key];
    };
    for (Event e : events) {
      switch (e) {
        case kBeginArray:
          open.push_back(place(ojson::array()));
          break;
        case kBeginObject:
          open.push_back(place(ojson::object()));
          break;
        case kEndArray:
        case kEndObject:
          open.pop_back();
          break;
        case kKey:
          key = strings[i_string++];
          break;
        case kInt:
          place(ints[i_int++]);
          break;
        case kBigUInt:
          place(big[i_big++]);
          break;
        case kFloat:
          place(floats[i_float++]);
          break;
        case kString:
          place(strings[i_string++]);
          break;
        case kTrue:
          place(true);
          break;
        case kFalse:
          place(false);
          break;
        case kNull:
          place(nullptr);
          break;
      }
    }
    return root;
  }

  std::vector<Event> events;
  std::vector<std::int64_t> ints;
  std::vector<std::uint64_t> big;  ///< integers beyond int64: sidecar values, never arrays
  std::vector<double> floats;
  std::vector<std::string> strings;

 private:
  // Rectangular's working space, kept between calls (it runs once per vector or matrix).
  mutable std::vector<std::size_t> counts_;
  mutable std::vector<long long> dims_;
};

}  // namespace imuconv::pipeline::detail
