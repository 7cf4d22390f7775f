#include "imuconv/pipeline/input_registry.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>

#include <map>
#include <mutex>
#include <utility>

namespace imuconv::pipeline {
namespace {

constexpr const char* kGenericRole = "the input file";

struct Entry {
  FileIdentity file;
  RegisteredInput input;
};

struct Registry {
  std::mutex mutex;
  std::map<std::pair<dev_t, ino_t>, Entry> inputs;
};

Registry& TheRegistry() {
  static Registry* r = new Registry;  // never destroyed: readers may run during static teardown
  return *r;
}

/// statx with the fields an identity needs, and the file's type.
std::optional<FileIdentity> Identity(int dir_fd, const char* path, int flags, mode_t* mode) {
  struct statx stx {};
  if (::statx(dir_fd, path, flags, STATX_TYPE | STATX_INO | STATX_BTIME, &stx) != 0)
    return std::nullopt;
  FileIdentity id;
  id.dev = makedev(stx.stx_dev_major, stx.stx_dev_minor);
  id.ino = static_cast<ino_t>(stx.stx_ino);
  id.has_birth = (stx.stx_mask & STATX_BTIME) != 0;
  if (id.has_birth) {
    id.birth_sec = stx.stx_btime.tv_sec;
    id.birth_nsec = stx.stx_btime.tv_nsec;
  }
  if (mode) *mode = stx.stx_mode;
  return id;
}

void Record(const FileIdentity& file, const std::string& path, const std::string& role) {
  Registry& r = TheRegistry();
  const std::lock_guard<std::mutex> lock(r.mutex);
  const auto [it, added] =
      r.inputs.emplace(std::pair{file.dev, file.ino}, Entry{file, RegisteredInput{path, role}});
  if (added) return;
  // A recorded input whose inode number a newer file now has was deleted: the newer file is the
  // input now.
  if (!it->second.file.same_file(file)) {
    it->second = Entry{file, RegisteredInput{path, role}};
    return;
  }
  // The first name stays; a role more precise than the opener's generic one replaces it (the
  // pipeline file is opened as any JSON file is, then said to be the pipeline).
  if (it->second.input.role == kGenericRole && role != kGenericRole)
    it->second.input = RegisteredInput{path, role};
}

void RecordIfRegular(const std::optional<FileIdentity>& file, mode_t mode, const std::string& path,
                     const std::string& role) {
  if (file && S_ISREG(mode)) Record(*file, path, role);
}

}  // namespace

bool FileIdentity::same_file(const FileIdentity& other) const {
  if (dev != other.dev || ino != other.ino) return false;
  if (!has_birth || !other.has_birth) return true;  // unknown: the inode decides, as before
  return birth_sec == other.birth_sec && birth_nsec == other.birth_nsec;
}

std::optional<FileIdentity> IdentityOf(int fd) { return Identity(fd, "", AT_EMPTY_PATH, nullptr); }

std::optional<FileIdentity> IdentityAt(int dir_fd, const std::string& path, bool follow_links) {
  return Identity(dir_fd, path.c_str(), follow_links ? 0 : AT_SYMLINK_NOFOLLOW, nullptr);
}

void RegisterInputDescriptor(int fd, const std::string& path, const std::string& role) {
  mode_t mode = 0;
  const auto file = Identity(fd, "", AT_EMPTY_PATH, &mode);
  RecordIfRegular(file, mode, path, role);
}

void RegisterInputPath(const std::string& path, const std::string& role) {
  mode_t mode = 0;
  const auto file = Identity(AT_FDCWD, path.c_str(), 0, &mode);
  RecordIfRegular(file, mode, path, role);
}

std::optional<RegisteredInput> FindRegisteredInput(const FileIdentity& file) {
  Registry& r = TheRegistry();
  const std::lock_guard<std::mutex> lock(r.mutex);
  const auto it = r.inputs.find({file.dev, file.ino});
  if (it == r.inputs.end() || !it->second.file.same_file(file)) return std::nullopt;
  return it->second.input;
}

}  // namespace imuconv::pipeline
