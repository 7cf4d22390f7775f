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
//     whole mode, set-id and sticky bits included, its owner and group when we may set them,
//     and its extended attributes (user.*, ACLs; those we may not set, such as security.* for
//     a user, are named in a warning on stderr); a new one gets 0666 & ~umask;
//   - a symbolic link: followed to its final target, which is then treated as above (the
//     link stays a link);
//   - anything else (a directory, a socket, a block device) is refused, and so is a regular
//     file with more than one hard link: renaming over one name would silently split it from
//     the others, and writing into it in place could leave every name with half a document.
// Written-through text is spooled to an unlinked temporary file ($TMPDIR, else /tmp) until
// commit() copies it through, so that a run that fails writes nothing anywhere (as for a file,
// whose temporary is then removed) and memory stays flat however large the document.
//
// An output is never an input: when it is made and again at commit(), the destination (by
// device and inode, links followed) is compared with every file this process has read
// (imuconv/pipeline/input_registry.h) and every shared object it has loaded, and refused
// naming the input. refuse_if_same() adds a file not read yet (checked before a run starts),
// refuse_if_same_output() another output of the same command.
// A file the output opens never takes descriptors 0-2 (standard_descriptors.h). The rules in
// one place: docs/outputs.md. Temporaries are removed by the destructor on every failure path
// and, once RemoveTemporariesOnSignal() has been called, on SIGINT, SIGTERM, SIGHUP and
// SIGPIPE too.
#pragma once

#include <sys/types.h>

#include <optional>
#include <string>
#include <string_view>

#include "imuconv/pipeline/input_registry.h"

namespace imuconv::pipeline {

class OutputFile {
 public:
  enum class Mode {
    Replace,       ///< a regular file (existing or new), replaced by renaming a temporary
    WriteThrough,  ///< a character device, a FIFO, or one of our descriptors
  };

  /// An output that must stay inside a directory (a pipeline's own "output"): the file written,
  /// after every symbolic link is resolved, lies in `directory` or below it, and is not one of
  /// our descriptors. `named_by` starts the message of a refusal ("P.json: /output").
  struct Confinement {
    std::string directory;
    std::string named_by;
  };

  /// Examines `path` and throws imuconv::Error naming it when it cannot be an output (the
  /// kinds above, a missing or unwritable directory, a descriptor not open for writing, an
  /// input of this process, outside `within`). An empty path is refused: a caller that means
  /// standard output says "-".
  explicit OutputFile(std::string path, std::optional<Confinement> within = std::nullopt);
  /// An output that was not committed is discarded: the temporary is removed, a
  /// written-through output's spool closed (it was unlinked when made, so nothing is left). A
  /// reader already waiting on a FIFO is sent end-of-file (no data) rather than left waiting for
  /// ever.
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
  /// Throws imuconv::Error when `other`, another output of the same command, would write this
  /// file too: "ROLE PATH and OTHER_ROLE OTHER_PATH name the same file (FILE); ..." (roles as
  /// the user gave them: "--tum", "-o"). Compared as the files the two will write, not as
  /// names: an existing file by its identity (device and inode, links followed), a file not
  /// created yet by its directory's identity and its name there, so "x", "./x", "sub/../x", an
  /// absolute path and a link to it are one file while "x" and "sub/x" are two.
  void refuse_if_same_output(const std::string& role, const OutputFile& other,
                             const std::string& other_role) const;

  /// Appends text: into the temporary (created on the first call) or the spool.
  void write(std::string_view text);
  /// Completes the output: flush and rename, or copy the spool through. Throws
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
  void create_spool();
  void check_confined() const;
  /// Throws (through fail()) when the file with this identity is an input or a loaded object.
  void refuse_input(const FileIdentity& file);
  void keep_attributes();
  void discard() noexcept;
  [[noreturn]] void fail(const std::string& what, int err);

  std::string path_, target_, dir_, tmp_;
  std::optional<Confinement> within_;
  int dir_fd_ = -1;  ///< the target's directory, held from examination to rename
  Mode mode_ = Mode::Replace;
  int fd_target_ = -1;  ///< our descriptor N when the path names one
  bool exists_ = false;
  bool fifo_ = false;
  FileIdentity identity_;  ///< the destination's, when it exists
  mode_t perms_ = 0;       ///< the mode bits (07777) for the replaced file
  uid_t uid_ = 0;
  gid_t gid_ = 0;
  int fd_ = -1;    ///< the open temporary
  int slot_ = -1;  ///< its entry in the signal handler's list
  bool committed_ = false;
  int spool_fd_ = -1;  ///< write-through text, until commit(): an unlinked temporary file
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
