// Hand validation of JSON documents: a Node is a value together with its JSON pointer;
// every accessor reports what is wrong at that pointer into a Checker and returns nothing,
// so that one pass collects every error of a document.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <initializer_list>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "imuconv/pipeline/errors.h"
#include "imuconv/types.h"

namespace imuconv::pipeline {

using json = nlohmann::json;

/// Text from a document (a key, a string value) for a message: escaped with Printable, in
/// quotes, cut after 80 bytes with "...".
std::string QuotedShort(std::string_view s);
/// RFC 6901 escaping of one reference token ("~" -> "~0", "/" -> "~1").
std::string PointerToken(std::string_view key);
/// "an object", "a string", ... for messages.
std::string TypeName(const json& j);

/// Collects the issues of one document. It counts every issue but stores only the first
/// kMaxStored (a hostile document can hold millions of problems; the message shows
/// ConfigError::kShownIssues of them anyway).
class Checker {
 public:
  static constexpr std::size_t kMaxStored = 100;
  explicit Checker(std::string file) : file_(std::move(file)) {}
  void error(std::string pointer, std::string message) {
    ++total_;
    if (issues_.size() < kMaxStored) issues_.push_back({std::move(pointer), std::move(message)});
  }
  bool ok() const noexcept { return total_ == 0; }
  /// Every issue reported so far, stored or not (callers compare counts to see whether a
  /// check added one).
  std::size_t count() const noexcept { return total_; }
  const std::string& file() const noexcept { return file_; }
  /// The stored issues: the first kMaxStored.
  const std::vector<Issue>& issues() const noexcept { return issues_; }
  /// Throws ConfigError with the stored issues and the total count, if there is any.
  void throw_if_errors() const;

 private:
  std::string file_;
  std::vector<Issue> issues_;
  std::size_t total_ = 0;
};

class Node {
 public:
  Node(const json& j, std::string pointer, Checker& checker)
      : j_(&j), ptr_(std::move(pointer)), c_(&checker) {}
  const json& value() const noexcept { return *j_; }
  const std::string& pointer() const noexcept { return ptr_; }
  Checker& checker() const noexcept { return *c_; }
  std::string child_pointer(std::string_view key) const { return ptr_ + "/" + PointerToken(key); }
  std::string child_pointer(std::size_t i) const { return ptr_ + "/" + std::to_string(i); }

  void fail(std::string message) const { c_->error(ptr_, std::move(message)); }

  bool is_object() const noexcept { return j_->is_object(); }
  bool is_array() const noexcept { return j_->is_array(); }
  bool is_string() const noexcept { return j_->is_string(); }
  bool has(std::string_view key) const { return j_->is_object() && j_->contains(key); }
  /// Child by key or index; the caller checks has() / the size first.
  Node operator[](std::string_view key) const {
    return Node(j_->at(std::string(key)), child_pointer(key), *c_);
  }
  Node operator[](std::size_t i) const { return Node(j_->at(i), child_pointer(i), *c_); }
  std::size_t size() const noexcept { return j_->size(); }

  /// Checks that this is an object whose keys are all in `allowed`; reports each unknown
  /// key at its own pointer. Returns false (reporting it) if this is not an object.
  bool expect_object(std::initializer_list<std::string_view> allowed) const;
  bool expect_object(const std::vector<std::string>& allowed) const;
  /// The child `key` of this object; reports "required key is missing" at its pointer when
  /// `required` and absent. Returns nothing when absent or when this is not an object.
  std::optional<Node> get(std::string_view key, bool required) const;

  // ---- typed reads: report "expected ..." at this pointer and return nothing if wrong ----
  std::optional<double> number() const;
  std::optional<std::int64_t> integer() const;
  std::optional<bool> boolean() const;
  std::optional<std::string> string() const;
  /// One of `choices` (reported with the list of accepted values).
  std::optional<std::string> one_of(std::initializer_list<std::string_view> choices) const;
  std::optional<std::string> one_of(const std::vector<std::string>& choices,
                                    std::string_view what) const;
  std::optional<std::vector<std::string>> string_list(bool allow_empty = false) const;
  /// string_list() whose items are distinct: for lists of ids that each become a key of an
  /// output object (a convention listed twice would write a key twice, which no JSON reader
  /// takes). An item equal to an earlier one is reported at its own pointer ("'x' is listed
  /// twice"), as "omit" does, and nothing is returned.
  std::optional<std::vector<std::string>> distinct_string_list(bool allow_empty = false) const;
  std::optional<std::vector<double>> number_list(std::size_t min_size = 0) const;
  std::optional<Vec3> vec3() const;
  /// Fixed-size vector of n numbers.
  std::optional<Eigen::VectorXd> vector(Eigen::Index n) const;
  /// rows x cols matrix written as an array of rows (row-major).
  std::optional<Eigen::MatrixXd> matrix(Eigen::Index rows, Eigen::Index cols) const;

  // ---- the same on a child key: get(key, required) then the typed read ----
  std::optional<double> number(std::string_view key, bool required) const;
  std::optional<std::int64_t> integer(std::string_view key, bool required) const;
  std::optional<bool> boolean(std::string_view key, bool required) const;
  std::optional<std::string> string(std::string_view key, bool required) const;
  std::optional<Vec3> vec3(std::string_view key, bool required) const;

 private:
  const json* j_;
  std::string ptr_;
  Checker* c_;
};

}  // namespace imuconv::pipeline
