#include "imuconv/pipeline/input_registry.h"

#include <sys/stat.h>

#include <map>
#include <mutex>
#include <utility>

namespace imuconv::pipeline {
namespace {

constexpr const char* kGenericRole = "the input file";

struct Registry {
  std::mutex mutex;
  std::map<std::pair<dev_t, ino_t>, RegisteredInput> inputs;
};

Registry& TheRegistry() {
  static Registry* r = new Registry;  // never destroyed: readers may run during static teardown
  return *r;
}

void Record(const struct stat& st, const std::string& path, const std::string& role) {
  if (!S_ISREG(st.st_mode)) return;
  Registry& r = TheRegistry();
  const std::lock_guard<std::mutex> lock(r.mutex);
  const auto [it, added] =
      r.inputs.emplace(std::pair{st.st_dev, st.st_ino}, RegisteredInput{path, role});
  // The first name stays; a role more precise than the opener's generic one replaces it (the
  // pipeline file is opened as any JSON file is, then said to be the pipeline).
  if (!added && it->second.role == kGenericRole && role != kGenericRole)
    it->second = RegisteredInput{path, role};
}

}  // namespace

void RegisterInputDescriptor(int fd, const std::string& path, const std::string& role) {
  struct stat st {};
  if (::fstat(fd, &st) == 0) Record(st, path, role);
}

void RegisterInputPath(const std::string& path, const std::string& role) {
  struct stat st {};
  if (::stat(path.c_str(), &st) == 0) Record(st, path, role);
}

std::optional<RegisteredInput> FindRegisteredInput(dev_t dev, ino_t ino) {
  Registry& r = TheRegistry();
  const std::lock_guard<std::mutex> lock(r.mutex);
  const auto it = r.inputs.find({dev, ino});
  if (it == r.inputs.end()) return std::nullopt;
  return it->second;
}

}  // namespace imuconv::pipeline
