// Every file this process reads, by identity: the rule "an output is never an input"
// (docs/outputs.md).
//
// Each reader records the files it opens here (data::InputFile does for every pipeline source,
// JSON document and Kalibr yaml; the montecarlo shard reader, imuconv merge and the shard digest
// for theirs), and OutputFile asks here, when it is made and again when it commits, whether its
// destination is one of them. A file is known by its device and inode as the open descriptor
// reports them, so a symbolic link, a hard link, a bind mount or /dev/fd/N naming the same file
// are all the same input, whatever the spelling. An input read after the output was opened
// counts too (the commit-time check sees it). Inode numbers are reused: a file created after an
// input was deleted may get the input's number. Where the file system records a birth time
// (statx's STATX_BTIME: ext4, xfs, btrfs, tmpfs), it is part of the identity, so such a file is
// not taken for the input (a long-lived process, such as the Python module, meets this when it
// writes into a directory that replaced one it read from).
//
// Process-wide and thread-safe; an entry is never removed (a long-lived process, such as the
// Python module, holds one entry per distinct file it has read).
#pragma once

#include <sys/types.h>

#include <optional>
#include <string>

namespace imuconv::pipeline {

/// What an output is compared against: how the input was named and in what role.
struct RegisteredInput {
  std::string path;  ///< as the reader named it (the first name it was read by)
  std::string role;  ///< "the input file", "a shard", "the case file", ...
};

/// A file as the kernel knows it: device, inode and, where recorded, birth time.
struct FileIdentity {
  dev_t dev = 0;
  ino_t ino = 0;
  bool has_birth = false;  ///< the file system gave a birth time
  long long birth_sec = 0;
  unsigned birth_nsec = 0;
  /// Same device and inode, and the same birth time where both know one.
  bool same_file(const FileIdentity& other) const;
};

/// The identity of the file open as `fd`; nullopt if fd is not open.
std::optional<FileIdentity> IdentityOf(int fd);
/// The identity of `path` (relative to dir_fd, e.g. AT_FDCWD), following a final symbolic link
/// only when `follow_links`; nullopt if it cannot be examined (errno says why).
std::optional<FileIdentity> IdentityAt(int dir_fd, const std::string& path, bool follow_links);

/// Records the file open as `fd` (read by `path`, in `role`). Only regular files are recorded:
/// a device or FIFO is not content the tool could destroy by replacing it.
void RegisterInputDescriptor(int fd, const std::string& path,
                             const std::string& role = "the input file");
/// Records the file `path` names (links followed); a missing file records nothing (it fails
/// where it is read). For readers that do not hold a descriptor (std::ifstream), and to give a
/// file already recorded as "the input file" a more precise role ("the pipeline").
void RegisterInputPath(const std::string& path, const std::string& role = "the input file");
/// The input that is this file, if this process has read it.
std::optional<RegisteredInput> FindRegisteredInput(const FileIdentity& file);

}  // namespace imuconv::pipeline
