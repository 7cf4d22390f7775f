// The timing checks of timing.h applied to the rows a file reader kept, as ReadError with the
// file and the line of the row after a gap (or no line, for the rate of the whole series).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "imuconv/pipeline/timing.h"

namespace imuconv::pipeline::data {

/// `t` and `lines`: the kept rows; `window`: the times the median period is taken from
/// (RangeKeeper::window()).
void ThrowIfTimingIssue(const std::string& path, const std::vector<double>& t,
                        const std::vector<std::size_t>& lines, const std::vector<double>& window,
                        const TimingPolicy& policy, TimeUnit declared, TimeSource source);

}  // namespace imuconv::pipeline::data
