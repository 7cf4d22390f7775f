#include "read_timing.h"

#include "imuconv/pipeline/errors.h"

namespace imuconv::pipeline::data {

void ThrowIfTimingIssue(const std::string& path, const std::vector<double>& t,
                        const std::vector<std::size_t>& lines, const std::vector<double>& window,
                        const TimingPolicy& policy, TimeUnit declared, TimeSource source) {
  const auto issue = FindTimingIssue(t, MedianPeriod(window), policy, declared, source);
  if (!issue) return;
  const std::size_t line = issue->kind == TimingIssue::Kind::gap && issue->index < lines.size()
                               ? lines[issue->index]
                               : 0;
  throw ReadError(path, line, issue->message);
}

}  // namespace imuconv::pipeline::data
