// The first bytes of an input, read as every input is (src/io/input_file.h: a regular file only,
// opened without blocking and checked again on the open descriptor, and recorded as an input
// that no output may replace): for a command that must tell what kind of file it was given
// before handing it to its reader (imuconv merge: a shard of imuconv montecarlo, or one of
// imuconv run's). A FIFO, a device or a directory is refused at once, never waited on.
#pragma once

#include <cstddef>
#include <string>

namespace imuconv::pipeline {

/// Up to the first `n` bytes of the regular file `path` (fewer when it is shorter). Throws
/// ReadError naming the file when it is missing, unreadable or not a regular file ("ff: is a
/// FIFO, not a regular file").
[[nodiscard]] std::string ReadInputStart(const std::string& path, std::size_t n);

}  // namespace imuconv::pipeline
