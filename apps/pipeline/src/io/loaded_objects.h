// The files this process runs from: the program itself and every shared object loaded into it
// (plugins, libraries, the Python module). No output may replace one (docs/outputs.md); the
// OutputFile asks here (output_file.cpp).
#pragma once

#include <string>
#include <vector>

namespace imuconv::pipeline::loaded_objects {

/// A file the process runs from, and its role in a message.
struct LoadedObject {
  std::string path;
  const char* role;  ///< "the running program" or "the loaded plugin or library"
};

/// The running program first, then every shared object loaded, as the dynamic linker lists them.
std::vector<LoadedObject> List();

}  // namespace imuconv::pipeline::loaded_objects
