#include "descriptor_io.h"

#include <poll.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <vector>

namespace imuconv::pipeline {

int WriteAll(int fd, std::string_view text) {
  std::size_t done = 0;
  while (done < text.size()) {
    const std::size_t chunk = std::min<std::size_t>(text.size() - done, std::size_t{1} << 30);
    const ssize_t w = ::write(fd, text.data() + done, chunk);
    if (w < 0) {
      if (errno == EINTR) continue;
      if (errno == EAGAIN || errno == EWOULDBLOCK) {
        pollfd p{fd, POLLOUT, 0};
        ::poll(&p, 1, -1);
        continue;
      }
      return errno;
    }
    done += static_cast<std::size_t>(w);
  }
  return 0;
}

int CopyThrough(int fd, int to) {
  std::vector<char> buf(std::size_t{1} << 20);
  off_t at = 0;
  for (;;) {
    const ssize_t n = ::pread(fd, buf.data(), buf.size(), at);
    if (n < 0) {
      if (errno == EINTR) continue;
      return errno;
    }
    if (n == 0) return 0;
    if (const int err = WriteAll(to, std::string_view(buf.data(), static_cast<std::size_t>(n))))
      return err;
    at += n;
  }
}

}  // namespace imuconv::pipeline
