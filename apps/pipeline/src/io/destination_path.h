// What an output path names, examined before anything is created: its kind, whether it is one of
// this process's descriptors, where its links lead, and a temporary's name beside it.
#pragma once

#include <sys/types.h>

#include <optional>
#include <string>

namespace imuconv::pipeline::destination {

/// "a regular file", "a FIFO", ... for messages.
std::string KindOf(mode_t m);
/// N when `p` names this process's descriptor N (-, /dev/stdout, /dev/fd/N, /proc/self/fd/N, ...).
std::optional<int> OwnDescriptor(const std::string& p);
/// The target of the symbolic link `p`; throws Error naming `shown`.
std::string ReadLink(const std::string& p, const std::string& shown);
/// 12 characters of [A-Za-z0-9] (71 bits) for a temporary's name.
std::string RandomSuffix();
/// The real path of `p` (every link resolved), or nullopt with errno set.
std::optional<std::string> RealPath(const std::string& p);
/// `inner` is `outer` or lies below it (both real paths).
bool IsInside(const std::string& inner, const std::string& outer);

}  // namespace imuconv::pipeline::destination
