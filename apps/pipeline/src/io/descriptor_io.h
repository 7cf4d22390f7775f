// Writing to a descriptor whole: the output file's temporary, its spool and a written-through
// destination all go through these.
#pragma once

#include <string_view>

namespace imuconv::pipeline {

/// Writes everything, through EINTR, short writes and a non-blocking descriptor; 0 or errno.
int WriteAll(int fd, std::string_view text);

/// Copies `fd`'s bytes from offset 0 to `to`; 0 or errno. A fixed buffer: memory does not grow
/// with the document.
int CopyThrough(int fd, int to);

}  // namespace imuconv::pipeline
