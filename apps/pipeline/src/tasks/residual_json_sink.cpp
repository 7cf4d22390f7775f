#include "residual_json_sink.h"

#include <Eigen/Core>
#include <cmath>
#include <cstring>
#include <exception>

#include "imuconv/printable.h"
#include "imuconv/utf8.h"

namespace imuconv::pipeline {
namespace {

/// Longest member name taken from a plugin (the built-in ones are at most 20 characters).
constexpr std::size_t kMaxNameLength = 64;

}  // namespace

void ResidualJsonSink::record(std::string message) noexcept {
  if (problem_.empty()) problem_ = std::move(message);
}

bool ResidualJsonSink::take_name(const char* name) noexcept {
  if (!problem_.empty()) return false;
  try {
    if (name == nullptr) {
      record("gave a null name");
      return false;
    }
    const std::string_view s(name, strnlen(name, kMaxNameLength + 1));
    if (s.empty() || s.size() > kMaxNameLength || FirstInvalidUtf8(s) != std::string_view::npos) {
      record("gave the name " + Quoted(s.substr(0, kMaxNameLength)) +
             " (expected 1 to 64 bytes of UTF-8)");
      return false;
    }
    if (!names_.back().emplace(s).second) {
      record("wrote " + Quoted(s) + " twice in one group");
      return false;
    }
    return true;
  } catch (const std::exception& e) {
    record(e.what());
    return false;
  }
}

bool ResidualJsonSink::take_size(const char* name, long long rows, long long cols) noexcept {
  if (rows < 1 || cols < 1 || numbers_ + rows * cols > kMaxNumbers) {
    record("gave " + std::string(name) + " a size of " + std::to_string(rows) + " x " +
           std::to_string(cols) + " (expected at least 1 x 1 and at most " +
           std::to_string(kMaxNumbers) + " numbers in all)");
    return false;
  }
  numbers_ += rows * cols;
  return true;
}

void ResidualJsonSink::begin_group(const char* name) noexcept {
  if (!take_name(name)) return;
  try {
    w_.key(name);
    w_.begin_object();
    names_.emplace_back();
  } catch (const std::exception& e) {
    record(e.what());
  }
}

void ResidualJsonSink::end_group() noexcept {
  if (!problem_.empty()) return;
  if (names_.size() < 2) {
    record("closed a group it had not opened");
    return;
  }
  try {
    w_.end_object();
    names_.pop_back();
  } catch (const std::exception& e) {
    record(e.what());
  }
}

void ResidualJsonSink::vector(const char* name, const double* values, int size) noexcept {
  if (!take_name(name) || !take_size(Quoted(name).c_str(), size, 1)) return;
  if (values == nullptr) return record("gave " + Quoted(name) + " a null array");
  try {
    w_.key(name);
    w_.vector(Eigen::Map<const Eigen::VectorXd>(values, size));  // throws for a non-finite value
  } catch (const std::exception& e) {
    record(e.what());
  }
}

void ResidualJsonSink::matrix(const char* name, const double* row_major, int rows,
                              int cols) noexcept {
  if (!take_name(name) || !take_size(Quoted(name).c_str(), rows, cols)) return;
  if (row_major == nullptr) return record("gave " + Quoted(name) + " a null array");
  try {
    using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
    w_.key(name);
    w_.matrix(Eigen::Map<const RowMajor>(row_major, rows, cols));
  } catch (const std::exception& e) {
    record(e.what());
  }
}

void ResidualJsonSink::mahalanobis_squared(double value) noexcept {
  if (!problem_.empty()) return;
  if (distance_) return record("gave its squared Mahalanobis distance twice");
  if (!std::isfinite(value) || value < 0.0)
    return record("gave a squared Mahalanobis distance of " + std::to_string(value) +
                  " (expected a finite number >= 0)");
  distance_ = value;
}

std::string ResidualJsonSink::problem() const {
  if (!problem_.empty()) return problem_;
  if (names_.size() > 1) return "left a group open";
  return {};
}

}  // namespace imuconv::pipeline
