// Where an output document goes, and how it gets there without destroying anything that is
// not ours.
//
// The destination is examined when an OutputFile is made (nothing is created then):
//   - "-", /dev/stdout, /dev/stderr, /dev/fd/N, /proc/self/fd/N: this process's descriptor N,
//     written through (its offset and append mode are the caller's, so `>> log` appends);
//   - a character device (/dev/null, a terminal) or a FIFO: written through, opened for
//     writing without O_CREAT or O_TRUNC; the node itself is never replaced;
//   - a regular file, or a name that does not exist yet: a temporary in the same directory,
//     created on the first write, flushed and renamed over it; an existing file keeps its
//     permission bits (and its owner when we may set it), a new one gets 0666 & ~umask;
//   - a symbolic link: followed to its final target, which is then treated as above (the
//     link stays a link);
//   - anything else (a directory, a socket, a block device) is refused, and so is a regular
//     file with more than one hard link: renaming over one name would silently split it from
//     the others, and writing into it in place could leave every name with half a document.
// Written-through text is held in memory until commit(), so that a run that fails writes
// nothing anywhere (as for a file, whose temporary is then removed).
//
// refuse_if_same() compares the destination's device and inode with an input's, so an output
// can never overwrite a file the run reads. Temporaries are removed by the destructor on every
// failure path and, once RemoveTemporariesOnSignal() has been called, on SIGINT, SIGTERM,
// SIGHUP and SIGPIPE too.
#pragma once

#include <sys/types.h>

#include <string>
#include <string_view>

namespace imuconv::pipeline {

class OutputFile {
 public:
  enum class Mode {
    Replace,       ///< a regular file (existing or new), replaced by renaming a temporary
    WriteThrough,  ///< a character device, a FIFO, or one of our descriptors
  };

  /// Examines `path` and throws imuconv::Error naming it when it cannot be an output (the
  /// kinds above, a missing or unwritable directory, a descriptor not open for writing).
  explicit OutputFile(std::string path);
  /// An output that was not committed is discarded: the temporary is removed, held text
  /// dropped. A reader already waiting on a FIFO is sent end-of-file (no data) rather than
  /// left waiting for ever.
  ~OutputFile();
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;

  /// Throws imuconv::Error if the destination is the same file (device and inode, symbolic
  /// links followed) as `other`, described in the message as `role` ("the pipeline", "the
  /// input file", "the case file", "the plugin"). An `other` that does not exist is no conflict.
  void refuse_if_same(const std::string& other, const std::string& role) const;
  /// The same against every shared object loaded in this process (the plugins a registry has
  /// loaded, the libraries): for a caller that does not hold the registry itself.
  void refuse_if_loaded_object() const;

  /// Appends text: into the temporary (created on the first call) or held for commit().
  void write(std::string_view text);
  /// Completes the output: flush and rename, or write the held text through. Throws
  /// imuconv::Error naming the path on failure (the temporary is then removed). A caller that
  /// also prints to std::cout flushes it first when is_stdout().
  void commit();

  Mode mode() const noexcept { return mode_; }
  /// The output is this process's standard output ("-", /dev/stdout, /dev/fd/1, ...):
  /// anything else meant for stdout must go elsewhere.
  bool is_stdout() const noexcept { return fd_target_ == 1; }
  const std::string& path() const noexcept { return path_; }
  /// The file actually written: the final target of a symbolic link, else path().
  const std::string& target() const noexcept { return target_; }

 private:
  void create_temporary();
  void discard() noexcept;
  [[noreturn]] void fail(const std::string& what, int err);

  std::string path_, target_, dir_, tmp_;
  Mode mode_ = Mode::Replace;
  int fd_target_ = -1;  ///< our descriptor N when the path names one
  bool exists_ = false;
  bool fifo_ = false;
  dev_t dev_ = 0;
  ino_t ino_ = 0;
  mode_t perms_ = 0;  ///< permission bits for the replaced file
  uid_t uid_ = 0;
  gid_t gid_ = 0;
  int fd_ = -1;    ///< the open temporary
  int slot_ = -1;  ///< its entry in the signal handler's list
  bool committed_ = false;
  std::string held_;  ///< write-through text, until commit()
  std::size_t written_ = 0, synced_ = 0;
};

/// The former name: every output is now an OutputFile.
using AtomicFile = OutputFile;

/// Writes `text` to `path` as an OutputFile does (atomically for a regular file, through for a
/// device or FIFO). On any failure nothing is left behind and Error is thrown.
void WriteFileAtomically(const std::string& path, const std::string& text);

/// Installs handlers for SIGINT, SIGTERM, SIGHUP and SIGPIPE (each one not ignored) that remove
/// every live temporary of this process and then die of the same signal, by its default
/// action, so the exit status is the signal's. Call once, early, from the program's main.
void RemoveTemporariesOnSignal();

}  // namespace imuconv::pipeline
