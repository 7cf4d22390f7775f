#include "imuconv/pipeline/json_check.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <string_view>

#include "imuconv/printable.h"

namespace imuconv::pipeline {
namespace {

// A pointer in a message: escaped, and cut at 200 bytes.
std::string PointerShown(std::string_view p) {
  constexpr std::size_t kMax = 200;
  if (p.size() <= kMax) return Printable(p);
  return Printable(p.substr(0, kMax)) + "...";
}

// The first ConfigError::kShownIssues issues, one per line, then how many more there were.
// File and pointer come from the user (a key can hold a newline): escaped.
std::string JoinIssues(const std::string& file, const std::vector<Issue>& issues,
                       std::size_t total) {
  const std::string shown_file = Printable(file);
  std::string s;
  const std::size_t n = std::min(issues.size(), ConfigError::kShownIssues);
  for (std::size_t i = 0; i < n; ++i) {
    if (i) s += "\n";
    s += shown_file + ": " +
         (issues[i].pointer.empty() ? std::string("(document)") : PointerShown(issues[i].pointer)) +
         ": " + issues[i].message;
  }
  if (total > n) s += "\n... and " + std::to_string(total - n) + " more problems in " + shown_file;
  return s;
}

template <typename List>
std::string JoinQuoted(const List& xs) {
  std::string s;
  bool first = true;
  for (const auto& x : xs) {
    if (!first) s += ", ";
    s += Quoted(x);
    first = false;
  }
  return s;
}

}  // namespace

ConfigError::ConfigError(std::string file, std::vector<Issue> issues, std::size_t total)
    : Error(JoinIssues(file, issues, std::max(total, issues.size()))),
      file_(std::move(file)),
      issues_(std::move(issues)),
      total_(std::max(total, issues_.size())) {}

ReadError::ReadError(std::string file, std::size_t line, const std::string& message)
    : Error(line > 0 ? Printable(file) + ":" + std::to_string(line) + ": " + message
                     : Printable(file) + ": " + message),
      file_(std::move(file)),
      line_(line) {}

std::string QuotedShort(std::string_view s) {
  constexpr std::size_t kMax = 80;  // the start is enough to find it; a key can be a megabyte long
  if (s.size() <= kMax) return Quoted(s);
  return "'" + Printable(s.substr(0, kMax)) + "...'";
}

std::string PointerToken(std::string_view key) {
  std::string s;
  s.reserve(key.size());
  for (char ch : key) {
    if (ch == '~')
      s += "~0";
    else if (ch == '/')
      s += "~1";
    else
      s += ch;
  }
  return s;
}

std::string TypeName(const json& j) {
  switch (j.type()) {
    case json::value_t::null:
      return "null";
    case json::value_t::object:
      return "an object";
    case json::value_t::array:
      return "an array";
    case json::value_t::string:
      return "a string";
    case json::value_t::boolean:
      return "a boolean";
    case json::value_t::number_integer:
    case json::value_t::number_unsigned:
      return "an integer";
    case json::value_t::number_float:
      return "a number";
    default:
      return "a value of unexpected type";
  }
}

void Checker::throw_if_errors() const {
  if (total_ > 0) throw ConfigError(file_, issues_, total_);
}

bool Node::expect_object(std::initializer_list<std::string_view> allowed) const {
  return expect_object(std::vector<std::string>(allowed.begin(), allowed.end()));
}

bool Node::expect_object(const std::vector<std::string>& allowed) const {
  if (!j_->is_object()) {
    fail("expected an object, found " + TypeName(*j_));
    return false;
  }
  for (auto it = j_->begin(); it != j_->end(); ++it) {
    bool known = false;
    for (const auto& a : allowed) known = known || it.key() == a;
    if (!known)
      c_->error(child_pointer(it.key()), "unknown key " + QuotedShort(it.key()) +
                                             " (allowed here: " + JoinQuoted(allowed) + ")");
  }
  return true;
}

std::optional<Node> Node::get(std::string_view key, bool required) const {
  if (!j_->is_object()) return std::nullopt;
  const auto it = j_->find(std::string(key));
  if (it == j_->end()) {
    if (required) c_->error(child_pointer(key), "required key is missing");
    return std::nullopt;
  }
  return Node(*it, child_pointer(key), *c_);
}

std::optional<double> Node::number() const {
  if (!j_->is_number()) {
    fail("expected a number, found " + TypeName(*j_));
    return std::nullopt;
  }
  const double v = j_->get<double>();
  if (!std::isfinite(v)) {
    fail("expected a finite number");
    return std::nullopt;
  }
  return v;
}

std::optional<std::int64_t> Node::integer() const {
  if (j_->is_number_integer() && !j_->is_number_unsigned()) return j_->get<std::int64_t>();
  if (j_->is_number_unsigned()) {
    const auto u = j_->get<std::uint64_t>();
    if (u <= static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max()))
      return static_cast<std::int64_t>(u);
    fail("integer out of range");
    return std::nullopt;
  }
  if (j_->is_number_float()) {
    const double v = j_->get<double>();
    if (std::isfinite(v) && v == std::floor(v) && std::abs(v) < 9.0e15)
      return static_cast<std::int64_t>(v);
  }
  fail("expected an integer, found " + TypeName(*j_));
  return std::nullopt;
}

std::optional<bool> Node::boolean() const {
  if (!j_->is_boolean()) {
    fail("expected true or false, found " + TypeName(*j_));
    return std::nullopt;
  }
  return j_->get<bool>();
}

std::optional<std::string> Node::string() const {
  if (!j_->is_string()) {
    fail("expected a string, found " + TypeName(*j_));
    return std::nullopt;
  }
  return j_->get<std::string>();
}

std::optional<std::string> Node::one_of(std::initializer_list<std::string_view> choices) const {
  return one_of(std::vector<std::string>(choices.begin(), choices.end()), "");
}

std::optional<std::string> Node::one_of(const std::vector<std::string>& choices,
                                        std::string_view what) const {
  const std::string label =
      what.empty() ? std::string("one of") : "one of the " + std::string(what);
  if (!j_->is_string()) {
    fail("expected " + label + " " + JoinQuoted(choices) + ", found " + TypeName(*j_));
    return std::nullopt;
  }
  const std::string s = j_->get<std::string>();
  for (const auto& c : choices)
    if (c == s) return s;
  fail("unknown value " + QuotedShort(s) + "; expected " + label + " " + JoinQuoted(choices));
  return std::nullopt;
}

namespace {
// Every element of the array n read by `read`; nothing if any is wrong (each one reported).
template <typename T>
std::optional<std::vector<T>> ReadElements(const Node& n, std::optional<T> (Node::*read)() const) {
  std::vector<T> out;
  bool ok = true;
  for (std::size_t i = 0; i < n.size(); ++i) {
    auto v = (n[i].*read)();
    if (v)
      out.push_back(std::move(*v));
    else
      ok = false;
  }
  if (!ok) return std::nullopt;
  return out;
}
}  // namespace

std::optional<std::vector<std::string>> Node::string_list(bool allow_empty) const {
  if (!j_->is_array()) {
    fail("expected an array of strings, found " + TypeName(*j_));
    return std::nullopt;
  }
  if (!allow_empty && j_->empty()) {
    fail("expected a non-empty array of strings");
    return std::nullopt;
  }
  return ReadElements(*this, &Node::string);
}

std::optional<std::vector<std::string>> Node::distinct_string_list(bool allow_empty) const {
  auto items = string_list(allow_empty);
  if (!items) return std::nullopt;
  // A set, not a search of the items before: a hostile list may be long.
  std::set<std::string_view> seen;
  bool distinct = true;
  for (std::size_t i = 0; i < items->size(); ++i)
    if (!seen.insert((*items)[i]).second) {
      (*this)[i].fail(QuotedShort((*items)[i]) + " is listed twice");
      distinct = false;
    }
  if (!distinct) return std::nullopt;
  return items;
}

std::optional<std::vector<double>> Node::number_list(std::size_t min_size) const {
  if (!j_->is_array()) {
    fail("expected an array of numbers, found " + TypeName(*j_));
    return std::nullopt;
  }
  if (j_->size() < min_size) {
    fail("expected at least " + std::to_string(min_size) + " numbers, found " +
         std::to_string(j_->size()));
    return std::nullopt;
  }
  return ReadElements(*this, &Node::number);
}

std::optional<Eigen::VectorXd> Node::vector(Eigen::Index n) const {
  if (!j_->is_array() || static_cast<Eigen::Index>(j_->size()) != n) {
    fail("expected an array of " + std::to_string(n) + " numbers, found " +
         (j_->is_array() ? "an array of " + std::to_string(j_->size()) : TypeName(*j_)));
    return std::nullopt;
  }
  Eigen::VectorXd v(n);
  bool ok = true;
  for (Eigen::Index i = 0; i < n; ++i) {
    auto x = (*this)[static_cast<std::size_t>(i)].number();
    if (x)
      v[i] = *x;
    else
      ok = false;
  }
  if (!ok) return std::nullopt;
  return v;
}

std::optional<Vec3> Node::vec3() const {
  auto v = vector(3);
  if (!v) return std::nullopt;
  return Vec3(*v);
}

std::optional<Eigen::MatrixXd> Node::matrix(Eigen::Index rows, Eigen::Index cols) const {
  const std::string shape = std::to_string(rows) + "x" + std::to_string(cols);
  if (!j_->is_array() || static_cast<Eigen::Index>(j_->size()) != rows) {
    fail("expected a " + shape + " matrix (an array of " + std::to_string(rows) + " rows), found " +
         (j_->is_array() ? "an array of " + std::to_string(j_->size()) : TypeName(*j_)));
    return std::nullopt;
  }
  Eigen::MatrixXd m(rows, cols);
  bool ok = true;
  for (Eigen::Index i = 0; i < rows; ++i) {
    auto r = (*this)[static_cast<std::size_t>(i)].vector(cols);
    if (r)
      m.row(i) = r->transpose();
    else
      ok = false;
  }
  if (!ok) return std::nullopt;
  return m;
}

namespace {
// The child `key` read by `read` (one of the typed reads above), as the keyed overloads do.
template <typename T>
std::optional<T> ReadChild(const Node& n, std::string_view key, bool required,
                           std::optional<T> (Node::*read)() const) {
  const auto child = n.get(key, required);
  return child ? ((*child).*read)() : std::nullopt;
}
}  // namespace

std::optional<double> Node::number(std::string_view key, bool required) const {
  return ReadChild(*this, key, required, &Node::number);
}
std::optional<std::int64_t> Node::integer(std::string_view key, bool required) const {
  return ReadChild(*this, key, required, &Node::integer);
}
std::optional<bool> Node::boolean(std::string_view key, bool required) const {
  return ReadChild(*this, key, required, &Node::boolean);
}
std::optional<std::string> Node::string(std::string_view key, bool required) const {
  return ReadChild(*this, key, required, &Node::string);
}
std::optional<Vec3> Node::vec3(std::string_view key, bool required) const {
  return ReadChild(*this, key, required, &Node::vec3);
}

}  // namespace imuconv::pipeline
