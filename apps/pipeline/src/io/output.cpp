#include "output.h"

namespace imuconv::pipeline {
namespace {
// Output text is handed to the sink in pieces of about this size.
constexpr std::size_t kFlushBytes = 1u << 20;
}  // namespace

void Output::flush(bool all) {
  if (buf_.empty() || (!all && buf_.size() < kFlushBytes)) return;
  sink(buf_);
  buf_.clear();
}

void Output::sink(std::string_view text) {
  try {
    sink_(text);
  } catch (const std::exception& e) {
    throw SinkFailure(e.what());
  }
}

}  // namespace imuconv::pipeline
