#include "imuconv/pipeline/standard_descriptors.h"

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <string>

#include "imuconv/registry.h"

namespace imuconv::pipeline {
namespace {
std::atomic<bool> g_was_closed[3];
}  // namespace

bool StandardDescriptorWasClosed(int fd) noexcept {
  return fd >= 0 && fd <= 2 && g_was_closed[fd].load();
}

void OpenClosedStandardDescriptors() {
  for (int fd = 0; fd <= 2; ++fd) {
    if (::fcntl(fd, F_GETFD) != -1 || errno != EBADF) continue;
    g_was_closed[fd].store(true);
    // open() returns the lowest free number, which is fd itself when every lower one is open
    // (they are: this loop goes up from 0). Not close-on-exec: a child inherits it as a
    // standard descriptor, as it would have inherited the closed one's replacement.
    const int got = ::open("/dev/null", fd == 0 ? O_RDONLY : O_WRONLY);
    if (got < 0)
      throw Error(
          "standard " +
          std::string(fd == 0   ? "input"
                      : fd == 1 ? "output"
                                : "error") +
          " (descriptor " + std::to_string(fd) +
          ") is closed and /dev/null cannot be opened in its place: " + std::strerror(errno));
    if (got != fd) {  // only if another thread opened something meanwhile
      const int moved = ::dup2(got, fd);
      const int err = errno;
      ::close(got);
      if (moved != fd)
        throw Error("standard descriptor " + std::to_string(fd) +
                    " is closed and cannot be reopened: " + std::strerror(err));
    }
  }
}

int AboveStandardDescriptors(int fd) noexcept {
  if (fd < 0 || fd > 2) return fd;
  const int moved = ::fcntl(fd, F_DUPFD_CLOEXEC, 3);
  const int err = errno;
  ::close(fd);
  errno = err;
  return moved;
}

}  // namespace imuconv::pipeline
