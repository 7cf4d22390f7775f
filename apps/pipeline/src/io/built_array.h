// An array of the output document that the result-array collector (array_collector.h) cannot
// take whole: one that is neither a vector or matrix given with its shape nor an array of
// objects (a list of block labels; in the parsed text, every array). It is built as a JSON value
// while its values arrive, and when it closes its shape is read off it: an N-d array when it is
// a rectangular array of numbers, else a value for the sidecar (the rule:
// imuconv/pipeline/result_arrays.h). Internal to imuconv_pipeline.
#pragma once

#include <cstddef>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace imuconv::pipeline::detail {

class BuiltArray {
 public:
  using ojson = nlohmann::ordered_json;

  /// Whether an array is being built (its values go here).
  bool building() const noexcept { return !open_.empty(); }
  /// Its open arrays and objects.
  std::size_t depth() const noexcept { return open_.size(); }

  /// Starts a new array (the previous one has been taken).
  void start() {
    root_ = ojson::array();
    open_.assign(1, &root_);
  }
  /// A value of the innermost open array, or of its open object under the last key().
  void add(ojson v) { place(std::move(v)); }
  void open(ojson container) { open_.push_back(place(std::move(container))); }
  void key(std::string_view name) { member_.assign(name.data(), name.size()); }
  /// Closes the innermost array or object; returns whether that was the whole array.
  bool close() {
    open_.pop_back();
    return open_.empty();
  }
  /// The whole array, once closed.
  ojson take() { return std::move(root_); }

  /// The numbers of a rectangular array: its shape, and its numbers in document order as reals
  /// (when any is a real; `mixed` when integers are among them) or as integers.
  struct Numbers {
    std::vector<std::size_t> shape;
    std::vector<double> reals;
    std::vector<std::int64_t> integers;
    bool real = false, mixed = false;
  };
  /// Whether the closed array is a rectangular array of numbers: numbers at one depth only,
  /// every array at a depth of one length, at least one number. Fills `n` (reused between
  /// calls); with `mixed`, its integers are still in `integers` and not in `reals`: the caller
  /// converts them (to_real) in document order through each_number().
  bool rectangular(Numbers& n) const {
    n.shape.clear();
    n.reals.clear();
    n.integers.clear();
    n.real = n.mixed = false;
    std::size_t leaf_depth = 0;  // where the numbers are, once one is met
    return Rectangular(root_, 0, leaf_depth, n) && leaf_depth != 0 && leaf_depth == n.shape.size();
  }
  /// f(number) for each number of the closed array, in document order.
  template <class F>
  void each_number(const F& f) const {
    EachLeaf(root_, f);
  }

 private:
  ojson* place(ojson v) {
    ojson& parent = *open_.back();
    if (parent.is_array()) {
      parent.push_back(std::move(v));
      return &parent.back();
    }
    ojson& m = parent[member_];
    m = std::move(v);
    return &m;
  }
  static bool Rectangular(const ojson& v, std::size_t depth, std::size_t& leaf_depth, Numbers& n) {
    if (v.is_array()) {
      if (depth < n.shape.size()) {
        if (n.shape[depth] != v.size()) return false;
      } else if (leaf_depth == 0 || depth < leaf_depth) {
        n.shape.push_back(v.size());  // the first array at this depth
      } else {
        return false;  // an array where others have numbers
      }
      for (const ojson& e : v)
        if (!Rectangular(e, depth + 1, leaf_depth, n)) return false;
      return true;
    }
    const bool is_int = v.type() == ojson::value_t::number_integer;
    if (!is_int && !v.is_number_float()) return false;
    if (leaf_depth == 0)
      leaf_depth = depth;
    else if (leaf_depth != depth)
      return false;
    if (is_int) {
      n.integers.push_back(v.get<std::int64_t>());
      n.mixed = n.mixed || n.real;
    } else {
      n.reals.push_back(v.get<double>());
      n.mixed = n.mixed || !n.integers.empty();
      n.real = true;
    }
    return true;
  }
  template <class F>
  static void EachLeaf(const ojson& v, const F& f) {
    if (!v.is_array()) return f(v);
    for (const ojson& e : v) EachLeaf(e, f);
  }

  ojson root_;
  std::vector<ojson*> open_;  ///< its open arrays and objects, innermost last
  std::string member_;        ///< the member of an object in it that comes next
};

}  // namespace imuconv::pipeline::detail
