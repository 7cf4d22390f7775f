// Status: how errors travel across the plugin boundary (exceptions never do).
#pragma once

#include <string>
#include <utility>

namespace imuconv {

class Status {
 public:
  Status() = default;
  static Status Ok() { return Status(); }
  static Status Error(std::string message) {
    Status s;
    s.ok_ = false;
    s.message_ = std::move(message);
    return s;
  }
  bool ok() const noexcept { return ok_; }
  const std::string& message() const noexcept { return message_; }
  explicit operator bool() const noexcept { return ok_; }

 private:
  bool ok_ = true;
  std::string message_;
};

}  // namespace imuconv
