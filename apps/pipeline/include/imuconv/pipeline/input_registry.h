// Every file this process reads, by identity: the rule "an output is never an input"
// (docs/outputs.md).
//
// Each reader records the files it opens here (data::InputFile does for every pipeline source,
// JSON document and Kalibr yaml; the montecarlo shard reader, imuconv merge and the shard digest
// for theirs), and OutputFile asks here, when it is made and again when it commits, whether its
// destination is one of them. A file is known by its device and inode as the open descriptor
// reports them, so a symbolic link, a hard link, a bind mount or /dev/fd/N naming the same file
// are all the same input, whatever the spelling. An input read after the output was opened
// counts too (the commit-time check sees it).
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

/// Records the file open as `fd` (read by `path`, in `role`). Only regular files are recorded:
/// a device or FIFO is not content the tool could destroy by replacing it.
void RegisterInputDescriptor(int fd, const std::string& path,
                             const std::string& role = "the input file");
/// Records the file `path` names (links followed); a missing file records nothing (it fails
/// where it is read). For readers that do not hold a descriptor (std::ifstream), and to give a
/// file already recorded as "the input file" a more precise role ("the pipeline").
void RegisterInputPath(const std::string& path, const std::string& role = "the input file");
/// The input with this device and inode, if this process has read one.
std::optional<RegisteredInput> FindRegisteredInput(dev_t dev, ino_t ino);

}  // namespace imuconv::pipeline
