// The built-in plugins, loaded once per benchmark program from the search path (as `imuconv`
// loads them); a file that does not load is reported on stderr under the program's name and the
// rest is used.
#pragma once

#include <cstdio>

#include "imuconv/printable.h"
#include "imuconv/registry.h"

namespace imuconv::bench {

inline Registry& BenchPlugins(const char* program) {
  static Registry* reg = [program] {
    auto* r = new Registry();
    for (const auto& i : r->load_search_path())
      std::fprintf(stderr, "%s: %s: %s\n", program, Printable(i.file).c_str(),
                   Printable(i.message).c_str());
    return r;
  }();
  return *reg;
}

}  // namespace imuconv::bench
