// Status: how errors travel across the plugin boundary (exceptions never do). [[nodiscard]]:
// a Status dropped is a failure nobody hears of, and the results it guards are then read as if
// they were computed; the compiler warns at every call that ignores one (write `(void)` and
// the reason where a failure truly cannot happen).
#pragma once

#include <string>
#include <utility>

namespace imuconv {

class [[nodiscard]] Status {
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
