#include "loaded_objects.h"

#include <link.h>

#include <filesystem>
#include <system_error>

namespace imuconv::pipeline::loaded_objects {

std::vector<LoadedObject> List() {
  // The program first: dl_iterate_phdr lists it with an empty name. /proc/self/exe names its
  // file whatever path started it, so an output named /proc/self/exe, or the binary's own path
  // (or the Python interpreter's, under the module), is refused instead of replacing it.
  std::error_code ec;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  std::vector<LoadedObject> objects{
      {ec ? std::string("/proc/self/exe") : exe.string(), "the running program"}};
  ::dl_iterate_phdr(
      [](dl_phdr_info* info, std::size_t, void* data) {
        if (info->dlpi_name && *info->dlpi_name)
          static_cast<std::vector<LoadedObject>*>(data)->push_back(
              {info->dlpi_name, "the loaded plugin or library"});
        return 0;
      },
      &objects);
  return objects;
}

}  // namespace imuconv::pipeline::loaded_objects
