#include "standard_output.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <streambuf>
#include <string>

#include "imuconv/cli/commands.h"
#include "imuconv/cli/exit_codes.h"

namespace imuconv::cli {
namespace {

/// Passes every character on to std::cout's own buffer (C's stdout, with sync_with_stdio) and
/// keeps errno of the first write that failed. It holds no text itself.
class FailureKeepingBuffer final : public std::streambuf {
 public:
  explicit FailureKeepingBuffer(std::streambuf* inner) : inner_(inner) {}
  bool failed() const noexcept { return failed_; }
  int error() const noexcept { return error_; }

 protected:
  int_type overflow(int_type c) override {
    if (traits_type::eq_int_type(c, traits_type::eof()))
      return sync() == 0 ? traits_type::not_eof(c) : traits_type::eof();
    return Watched(inner_->sputc(traits_type::to_char_type(c)),
                   [](int_type r) { return traits_type::eq_int_type(r, traits_type::eof()); });
  }
  std::streamsize xsputn(const char* s, std::streamsize n) override {
    return Watched(inner_->sputn(s, n), [n](std::streamsize r) { return r < n; });
  }
  int sync() override {
    return Watched(inner_->pubsync(), [](int r) { return r != 0; });
  }

 private:
  /// `result` of a write into the inner buffer, the first failure noted with errno as the failed
  /// write(2) under fwrite or fflush left it.
  template <typename R, typename Failed>
  R Watched(R result, Failed failed_if) {
    if (failed_if(result) && !failed_) {
      failed_ = true;
      error_ = errno;
    }
    return result;
  }

  std::streambuf* inner_;
  bool failed_ = false;
  int error_ = 0;
};

FailureKeepingBuffer* watched = nullptr;  // never deleted: std::cout uses it until exit

}  // namespace

void WatchStandardOutput() {
  if (watched) return;
  // Made once and kept: the streams are flushed after every static object is destroyed.
  watched = new FailureKeepingBuffer(std::cout.rdbuf());
  std::cout.rdbuf(watched);
}

int CompleteStandardOutput(int exit_code) {
  errno = 0;
  std::cout.flush();
  const bool flush_failed = std::fflush(stdout) != 0;
  int err = errno;
  bool failed = flush_failed || !std::cout.good() || std::ferror(stdout);
  if (watched && watched->failed()) {
    failed = true;
    err = watched->error();  // the first failure's reason
  }
  if (!failed) return exit_code;
  PrintError(std::string("standard output: cannot write the command's output (") +
             (err != 0 ? std::strerror(err) : "a write failed") + "): it is incomplete");
  return exit_code == kExitInternal ? kExitInternal : kExitBadInput;
}

}  // namespace imuconv::cli
