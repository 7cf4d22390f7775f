#include "imuconv/pipeline/output_file.h"

#include <fcntl.h>
#include <limits.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/xattr.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <optional>
#include <vector>

#include "descriptor_io.h"
#include "destination_path.h"
#include "imuconv/pipeline/input_registry.h"
#include "imuconv/pipeline/standard_descriptors.h"
#include "imuconv/printable.h"
#include "imuconv/registry.h"
#include "live_temporaries.h"
#include "loaded_objects.h"

namespace imuconv::pipeline {

namespace fs = std::filesystem;
using destination::IsInside;
using destination::KindOf;
using destination::OwnDescriptor;
using destination::RandomSuffix;
using destination::ReadLink;
using destination::RealPath;
using live_temporaries::Forget;
using live_temporaries::Remember;

OutputFile::OutputFile(std::string path, std::optional<Confinement> within)
    : path_(std::move(path)), within_(std::move(within)) {
  const std::string shown = Printable(path_);
  if (path_.empty())
    throw Error("the output path is empty; expected a file name, or '-' for standard output");
  if (path_.find('\0') != std::string::npos)
    throw Error(shown + ": a path cannot contain a NUL byte");

  // Follow symbolic links one at a time (a descriptor path is recognised before it is followed).
  std::string p = path_;
  struct stat st {};
  for (int links = 0;; ++links) {
    if (const auto n = OwnDescriptor(p)) {
      if (within_)
        throw Error(within_->named_by + ": " + shown + " leads to file descriptor " +
                    std::to_string(*n) +
                    " of this process, outside the pipeline's directory; expected a file inside it "
                    "(to write "
                    "anywhere else, give the output on the command line with -o)");
      if (StandardDescriptorWasClosed(*n))
        throw Error(shown + ": " +
                    std::string(*n == 0   ? "standard input"
                                : *n == 1 ? "standard output"
                                          : "standard error") +
                    " was closed when imuconv started (it is /dev/null now, so that no file takes "
                    "its number); give "
                    "the output a file name");
      struct stat fst {};
      if (::fstat(*n, &fst) != 0)
        throw Error(shown + ": file descriptor " + std::to_string(*n) + " is not open");
      const int flags = ::fcntl(*n, F_GETFL);
      if (flags < 0 || (flags & O_ACCMODE) == O_RDONLY)
        throw Error(shown + ": file descriptor " + std::to_string(*n) + " is not open for writing");
      mode_ = Mode::WriteThrough;
      fd_target_ = *n;
      target_ = path_;
      exists_ = true;
      identity_ = IdentityOf(*n).value_or(FileIdentity{fst.st_dev, fst.st_ino});
      if (const auto in = FindRegisteredInput(identity_))
        throw Error(shown + ": is the same file as " + in->role + " " + Printable(in->path) +
                    ": refusing to overwrite it; write the output elsewhere");
      return;
    }
    if (::lstat(p.c_str(), &st) != 0) {
      // A missing name is a new file (a missing directory is reported below).
      if (errno != ENOENT)
        throw Error(shown + ": cannot examine " + Printable(p) + ": " + std::strerror(errno));
      break;
    }
    if (!S_ISLNK(st.st_mode)) {
      exists_ = true;
      break;
    }
    if (links == 40)
      throw Error(shown +
                  ": more than 40 symbolic links to follow (a loop?); expected a file, a character "
                  "device or a FIFO");
    const fs::path to(ReadLink(p, shown));
    p = to.is_absolute() ? to.string() : (fs::path(p).parent_path() / to).string();
  }
  target_ = p;
  const std::string where =
      target_ == path_ ? shown : shown + " (a symbolic link to " + Printable(target_) + ")";
  dir_ = fs::path(target_).parent_path().string();
  if (dir_.empty()) dir_ = ".";
  if (within_) check_confined();

  if (exists_) {
    identity_ = IdentityAt(AT_FDCWD, p, false).value_or(FileIdentity{st.st_dev, st.st_ino});
    if (const auto in = FindRegisteredInput(identity_))
      throw Error(where + ": is the same file as " + in->role + " " + Printable(in->path) +
                  ": refusing to overwrite it; write the output elsewhere");
    if (S_ISCHR(st.st_mode) || S_ISFIFO(st.st_mode)) {
      // Written through: /dev/null must stay a device, a FIFO's reader must get the data.
      mode_ = Mode::WriteThrough;
      fifo_ = S_ISFIFO(st.st_mode);
      if (::faccessat(AT_FDCWD, target_.c_str(), W_OK, AT_EACCESS) != 0)
        throw Error(where + ": cannot write to this " + KindOf(st.st_mode).substr(2) + ": " +
                    std::strerror(errno));
      return;
    }
    if (!S_ISREG(st.st_mode))
      throw Error(where + ": is " + KindOf(st.st_mode) +
                  "; expected a regular file (replaced atomically), a character device or a FIFO "
                  "(written through)");
    if (st.st_nlink > 1)
      throw Error(where + ": has " + std::to_string(st.st_nlink) +
                  " hard links; replacing it would split them (the other names would keep the old "
                  "content) and "
                  "writing into it in place could leave them all with half a document: remove the "
                  "other links, or "
                  "write the output elsewhere");
    perms_ = st.st_mode & 07777;  // set-user-ID, set-group-ID and sticky bits too
    uid_ = st.st_uid;
    gid_ = st.st_gid;
  } else {
    // umask() is the only portable way to read the mask; it is set back at once.
    const mode_t mask = ::umask(0);
    ::umask(mask);
    perms_ = 0666 & ~mask;
  }
  mode_ = Mode::Replace;
  // Checked now, so that a run is not done in vain; the temporary itself waits for the first write.
  if (::faccessat(AT_FDCWD, dir_.c_str(), W_OK | X_OK, AT_EACCESS) != 0)
    throw Error(where + ": cannot create a temporary file in " + Printable(dir_) + ": " +
                std::strerror(errno));
  // The directory is held from here to the rename: the temporary is created in it and renamed
  // within it by descriptor, so a directory (or a link on the way to it) swapped meanwhile
  // cannot redirect the output elsewhere, out of a confinement least of all. O_PATH when the
  // directory may be written but not listed.
  dir_fd_ = ::open(dir_.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dir_fd_ < 0) dir_fd_ = ::open(dir_.c_str(), O_PATH | O_DIRECTORY | O_CLOEXEC);
  dir_fd_ = AboveStandardDescriptors(dir_fd_);
  if (dir_fd_ < 0)
    throw Error(where + ": cannot open its directory " + Printable(dir_) + ": " +
                std::strerror(errno));
  if (within_) {
    // The directory now held is the one checked (not one swapped in after the check).
    struct stat held {
    }, named{};
    if (::fstat(dir_fd_, &held) != 0 || ::stat(dir_.c_str(), &named) != 0 ||
        held.st_dev != named.st_dev || held.st_ino != named.st_ino) {
      ::close(dir_fd_);
      dir_fd_ = -1;
      throw Error(within_->named_by + ": " + shown +
                  ": its directory changed while it was examined; try again");
    }
  }
}

void OutputFile::check_confined() const {
  const std::string shown = Printable(path_);
  const auto root = RealPath(within_->directory.empty() ? "." : within_->directory);
  if (!root)
    throw Error(within_->named_by + ": cannot resolve the pipeline's directory " +
                Printable(within_->directory) + ": " + std::strerror(errno));
  // The final name is not a link (links were followed above), so the file written is the real
  // directory's entry of that name.
  const auto dir = RealPath(dir_);
  if (!dir)
    throw Error(within_->named_by + ": " + shown + ": cannot resolve its directory " +
                Printable(dir_) + ": " + std::strerror(errno));
  if (!IsInside(*dir, *root))
    throw Error(within_->named_by + ": " + shown + " leads outside the pipeline's directory " +
                Printable(*root) + " (to " +
                Printable((fs::path(*dir) / fs::path(target_).filename()).string()) +
                ", through a symbolic link); expected a file inside it (to write anywhere else, "
                "give the output on "
                "the command line with -o)");
}

OutputFile::~OutputFile() {
  discard();
  if (dir_fd_ >= 0) ::close(dir_fd_);
  if (fifo_ && !committed_) {
    // Non-blocking: this succeeds only when a reader is already waiting in open(), and then
    // closing at once gives it end-of-file with no data instead of a wait that never ends.
    const int fd = ::open(target_.c_str(), O_WRONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd >= 0) ::close(fd);
  }
}

void OutputFile::discard() noexcept {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
  if (!tmp_.empty()) {
    if (dir_fd_ >= 0)
      ::unlinkat(dir_fd_, fs::path(tmp_).filename().c_str(), 0);
    else
      ::unlink(tmp_.c_str());
  }
  tmp_.clear();
  Forget(slot_);
  slot_ = -1;
  if (spool_fd_ >= 0) ::close(spool_fd_);  // unlinked already: its space is freed with it
  spool_fd_ = -1;
}

void OutputFile::fail(const std::string& what, int err) {
  discard();
  throw Error(Printable(path_) + ": " + what +
              (err != 0 ? std::string(": ") + std::strerror(err) : std::string()));
}

void OutputFile::refuse_if_same_output(const std::string& role, const OutputFile& other,
                                       const std::string& other_role) const {
  // Names cannot be compared: "x" and "./x" normalise differently while neither exists (that
  // let one output replace the other), and a link to a new name shows nothing of its target.
  // The kernel's view can: both outputs were examined already, links followed, and a file to
  // be replaced or created is the entry of its final name in the directory held open (dir_fd_).
  bool same = exists_ && other.exists_ && identity_.same_file(other.identity_);
  const std::string leaf = fs::path(target_).filename().string();
  if (!same && mode_ == Mode::Replace && other.mode_ == Mode::Replace &&
      leaf == fs::path(other.target_).filename().string()) {
    struct stat a {
    }, b{};
    same = ::fstat(dir_fd_, &a) == 0 && ::fstat(other.dir_fd_, &b) == 0 && a.st_dev == b.st_dev &&
           a.st_ino == b.st_ino;
  }
  if (!same) return;
  // The one file, as the kernel will find it: the directory's real path and the name in it.
  std::string file = target_;
  if (mode_ == Mode::Replace)
    if (const auto dir = RealPath(dir_)) file = (fs::path(*dir) / leaf).string();
  throw Error(role + " " + Printable(path_) + " and " + other_role + " " + Printable(other.path_) +
              " name the same file (" + Printable(file) +
              "): one would replace the other; give each output a file of its own");
}

void OutputFile::refuse_if_same(const std::string& other, const std::string& role) const {
  if (!exists_) return;
  struct stat st {};
  if (::stat(other.c_str(), &st) != 0) return;  // an input that is missing fails when it is read
  if (st.st_dev == identity_.dev && st.st_ino == identity_.ino)
    throw Error(Printable(path_) + ": is the same file as " + role + " " + Printable(other) +
                ": refusing to overwrite it; write the output elsewhere");
}

void OutputFile::refuse_if_loaded_object() const {
  if (!exists_) return;
  for (const auto& o : loaded_objects::List()) refuse_if_same(o.path, o.role);
}

void OutputFile::refuse_input(const FileIdentity& file) {
  if (const auto in = FindRegisteredInput(file))
    fail("is the same file as " + in->role + " " + Printable(in->path) +
             ": refusing to overwrite it; write the output elsewhere",
         0);
  for (const auto& o : loaded_objects::List()) {
    struct stat st {};
    if (::stat(o.path.c_str(), &st) == 0 && st.st_dev == file.dev && st.st_ino == file.ino)
      fail("is the same file as " + std::string(o.role) + " " + Printable(o.path) +
               ": refusing to overwrite it; write the output elsewhere",
           0);
  }
}

void OutputFile::create_temporary() {
  const std::string base = "." + fs::path(target_).filename().string() + ".tmp.";
  // The name is entered in the signal handler's table before the file exists (O_EXCL), so
  // there is no moment at which our temporary exists unknown to the handler.
  for (int attempt = 0; attempt < 16; ++attempt) {
    const std::string leaf = base + RandomSuffix();
    const std::string name = (fs::path(dir_) / leaf).string();
    slot_ = Remember(name);
    if (slot_ < 0)
      fail("cannot create a temporary file: more than 16 open at once, or a path too long", 0);
    fd_ = AboveStandardDescriptors(
        ::openat(dir_fd_, leaf.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0600));
    if (fd_ >= 0) {
      tmp_ = name;
      return;
    }
    const int err = errno;
    Forget(slot_);
    slot_ = -1;
    if (err != EEXIST) fail("cannot create a temporary file in " + Printable(dir_), err);
  }
  fail("cannot create a temporary file in " + Printable(dir_) + ": 16 random names were all taken",
       0);
}

void OutputFile::create_spool() {
  // $TMPDIR as the user's choice of where large temporaries go, else /tmp. O_TMPFILE makes a
  // file with no name at all; where the file system lacks it, a named one is unlinked at once.
  const char* env = std::getenv("TMPDIR");
  const std::string dir = env && *env ? env : "/tmp";
  int fd = ::open(dir.c_str(), O_TMPFILE | O_RDWR | O_CLOEXEC, 0600);
  if (fd < 0) {
    std::string name = (fs::path(dir) / ("imuconv-spool-" + RandomSuffix())).string();
    fd = ::open(name.c_str(), O_RDWR | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
    if (fd >= 0) ::unlink(name.c_str());
  }
  spool_fd_ = AboveStandardDescriptors(fd);
  if (spool_fd_ < 0)
    fail("cannot create the spool file that holds the output until the run has succeeded, in " +
             Printable(dir) + " ($TMPDIR, else /tmp; set TMPDIR to a writable directory)",
         errno);
}

void OutputFile::write(std::string_view text) {
  if (committed_) throw Error(Printable(path_) + ": written after it was completed");
  if (mode_ == Mode::WriteThrough) {
    if (spool_fd_ < 0) create_spool();
    if (const int err = WriteAll(spool_fd_, text))
      fail("cannot write the spool file (in $TMPDIR, else /tmp)", err);
    return;
  }
  if (fd_ < 0) create_temporary();
  if (const int err = WriteAll(fd_, text))
    fail("cannot write the temporary file " + Printable(tmp_), err);
  written_ += text.size();
#ifdef SYNC_FILE_RANGE_WRITE
  // Large outputs: start writing back what is there while the rest is produced, so that the
  // final fsync has little left to wait for. Only a hint; errors surface at fsync.
  constexpr std::size_t kWriteBehind = 8u << 20;
  if (written_ - synced_ >= kWriteBehind) {
    ::sync_file_range(fd_, static_cast<off_t>(synced_), static_cast<off_t>(written_ - synced_),
                      SYNC_FILE_RANGE_WRITE);
    synced_ = written_;
  }
#endif
}

void OutputFile::keep_attributes() {
  // Extended attributes of the file replaced (user.*, system.posix_acl_* = ACLs, security.*,
  // trusted.*), copied to the temporary before the rename. An attribute the temporary already
  // has with the same value (an SELinux label given by the directory) needs nothing; one we may
  // not set (security.* or trusted.* for a user) is named in a warning: the output is still
  // written, without it.
  const ssize_t size = ::llistxattr(target_.c_str(), nullptr, 0);
  if (size <= 0) return;  // none, or a file system without them (ENOTSUP)
  std::vector<char> names(static_cast<std::size_t>(size));
  const ssize_t got = ::llistxattr(target_.c_str(), names.data(), names.size());
  if (got < 0) return;  // changed meanwhile: the file is being replaced anyway
  std::string lost;
  for (std::size_t i = 0; i < static_cast<std::size_t>(got);) {
    const std::string name(names.data() + i);
    i += name.size() + 1;
    if (name.empty()) continue;
    const ssize_t vsize = ::lgetxattr(target_.c_str(), name.c_str(), nullptr, 0);
    if (vsize < 0) continue;
    std::vector<char> value(static_cast<std::size_t>(vsize) + 1);
    const ssize_t vgot = ::lgetxattr(target_.c_str(), name.c_str(), value.data(), value.size());
    if (vgot < 0) continue;
    std::vector<char> have(value.size());
    const ssize_t hgot = ::fgetxattr(fd_, name.c_str(), have.data(), have.size());
    if (hgot == vgot && std::memcmp(have.data(), value.data(), static_cast<std::size_t>(vgot)) == 0)
      continue;
    if (::fsetxattr(fd_, name.c_str(), value.data(), static_cast<std::size_t>(vgot), 0) != 0)
      lost += (lost.empty() ? "" : ", ") + Printable(name) + " (" + std::strerror(errno) + ")";
  }
  if (!lost.empty())
    std::cerr << "imuconv: warning: " << Printable(path_)
              << ": the replaced file's extended attributes were not all kept; not kept: " << lost
              << "\n";
}

void OutputFile::commit() {
  if (committed_) throw Error(Printable(path_) + ": completed twice");
  const std::string shown = Printable(path_);
  if (mode_ == Mode::WriteThrough) {
    int fd = fd_target_;
    if (fd < 0) {
      // No O_CREAT, no O_TRUNC: the node is used as it is. A FIFO waits here for its reader.
      fd = AboveStandardDescriptors(::open(target_.c_str(), O_WRONLY | O_NOCTTY | O_CLOEXEC));
      if (fd < 0) fail("cannot open it for writing", errno);
    }
    // The node written is the one examined, and still not an input (one read since counts).
    if (const auto written = IdentityOf(fd)) {
      try {
        refuse_input(*written);
      } catch (...) {
        if (fd != fd_target_) ::close(fd);
        throw;
      }
    }
    int err = spool_fd_ >= 0 ? CopyThrough(spool_fd_, fd) : 0;
    if (fd != fd_target_ && ::close(fd) != 0 && err == 0) err = errno;
    discard();
    if (err != 0) throw Error(shown + ": cannot write to it: " + std::strerror(err));
    committed_ = true;
    return;
  }

  if (fd_ < 0) create_temporary();  // an empty document is still a document
  const std::string leaf = fs::path(target_).filename().string();
  // The destination may have changed while the run went on: never rename over anything but a
  // regular file with one name, nor over a file this process has read (input_registry.h).
  struct stat now {};
  if (::fstatat(dir_fd_, leaf.c_str(), &now, AT_SYMLINK_NOFOLLOW) == 0) {
    if (!S_ISREG(now.st_mode) || now.st_nlink > 1)
      fail("became " +
               (S_ISREG(now.st_mode) ? std::string("a file with several hard links")
                                     : KindOf(now.st_mode)) +
               " while the output was produced; it is left as it is",
           0);
    refuse_input(IdentityAt(dir_fd_, leaf, false).value_or(FileIdentity{now.st_dev, now.st_ino}));
  }
  // Keep the owner and group of a file we replace when we may (root: both; the owner: a group
  // of which they are a member), then its mode (after fchown, which clears set-id bits). The
  // kernel clears set-group-ID itself when we are not in the file's group; that is said below.
  if (exists_ && (uid_ != ::geteuid() || gid_ != ::getegid())) {
    if (::fchown(fd_, uid_, gid_) != 0) {
      [[maybe_unused]] const int ignored =
          ::fchown(fd_, static_cast<uid_t>(-1), gid_);  // then the owner is ours
    }
  }
  // A set-ID bit is kept only with the owner (group) it was given for: a file set-user-ID to
  // someone else must not become one set-user-ID to us.
  mode_t applied = perms_;
  if (exists_) {
    struct stat owned {};
    if (::fstat(fd_, &owned) == 0) {
      if (owned.st_uid != uid_) applied &= ~static_cast<mode_t>(S_ISUID);
      if (owned.st_gid != gid_) applied &= ~static_cast<mode_t>(S_ISGID);
    }
  }
  if (::fchmod(fd_, applied) != 0)
    fail("cannot set the permissions of the temporary file " + Printable(tmp_), errno);
  if (exists_) {
    keep_attributes();
    struct stat made {};
    if (::fstat(fd_, &made) == 0 && (made.st_mode & 07777) != perms_) {
      char want[8], have[8];
      std::snprintf(want, sizeof want, "%04o", static_cast<unsigned>(perms_));
      std::snprintf(have, sizeof have, "%04o", static_cast<unsigned>(made.st_mode & 07777));
      std::cerr << "imuconv: warning: " << shown << ": the replaced file's mode " << want
                << " could not be kept in full (a set-ID bit needs the file's owner or group, "
                   "which this process "
                   "cannot give it): "
                << have << " now\n";
    }
  }
  if (::fsync(fd_) != 0) fail("cannot flush the temporary file " + Printable(tmp_), errno);
  const int fd = fd_;
  fd_ = -1;
  if (::close(fd) != 0) fail("cannot close the temporary file " + Printable(tmp_), errno);
  if (::renameat(dir_fd_, fs::path(tmp_).filename().c_str(), dir_fd_, leaf.c_str()) != 0)
    fail("cannot rename the temporary file over it", errno);
  tmp_.clear();
  Forget(slot_);
  slot_ = -1;
  committed_ = true;
  // Make the rename itself durable; not every file system can sync a directory (nor can an
  // O_PATH descriptor), so a failure here is not an error (the data are on disk already).
  ::fsync(dir_fd_);
}

void WriteFileAtomically(const std::string& path, const std::string& text) {
  OutputFile f(path);
  f.write(text);
  f.commit();
}

}  // namespace imuconv::pipeline
