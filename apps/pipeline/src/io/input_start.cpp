#include "imuconv/pipeline/input_start.h"

#include "input_file.h"

namespace imuconv::pipeline {

std::string ReadInputStart(const std::string& path, std::size_t n) {
  data::InputFile in(path);
  std::string start(n, '\0');
  std::size_t used = 0;
  while (used < n) {
    const std::size_t got = in.read(start.data() + used, n - used);
    if (got == 0) break;  // the file is shorter
    used += got;
  }
  start.resize(used);
  return start;
}

}  // namespace imuconv::pipeline
