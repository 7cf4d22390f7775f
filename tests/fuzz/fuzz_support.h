// Shared by the libFuzzer targets: the input as a file (the readers under test take paths,
// and their file handling is part of what is fuzzed), and the rule for what counts as a
// finding.
//
// A reader may reject an input only with imuconv::Error (ConfigError, ReadError), whose
// message names the file. Anything else escaping it - another exception type, an error that
// does not name the file, a crash, a sanitizer report, a hang (-timeout) or an allocation
// beyond -malloc_limit_mb - is a finding, reported by abort() so that libFuzzer keeps the
// input.
#pragma once

#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

#include "imuconv/registry.h"

namespace imuconv::fuzz {

/// A file in the temp dir owned by this process, rewritten for every input.
class InputFile {
 public:
  explicit InputFile(const char* name) {
    const char* tmp = std::getenv("TMPDIR");
    path_ = std::string(tmp && *tmp ? tmp : "/tmp") + "/imuconv_fuzz_" + name + "_" +
            std::to_string(::getpid());
  }
  ~InputFile() { std::remove(path_.c_str()); }
  const std::string& write(const std::uint8_t* data, std::size_t size) {
    std::FILE* f = std::fopen(path_.c_str(), "wb");
    if (f == nullptr) Finding("cannot write the fuzz input file " + path_);
    if (size > 0 && std::fwrite(data, 1, size, f) != size) Finding("short write to " + path_);
    std::fclose(f);
    return path_;
  }
  const std::string& path() const { return path_; }

  [[noreturn]] static void Finding(const std::string& what) {
    std::fprintf(stderr, "imuconv fuzz finding: %s\n", what.c_str());
    std::abort();
  }

 private:
  std::string path_;
};

/// The registry of the built-in plugins, loaded once per process (loading checks every
/// convention's charts, far slower than one input).
inline const Registry& LoadedRegistry() {
  static const Registry* reg = [] {
    auto* r = new Registry();
    // A plugin that fails to load would leave the fuzzer testing less than it says: stop.
    for (const LoadIssue& i : r->load_search_path()) {
      std::fprintf(stderr, "fuzz: plugin failed to load: %s: %s\n", i.file.c_str(),
                   i.message.c_str());
      std::abort();
    }
    return r;
  }();
  return *reg;
}

/// Runs f(); an imuconv::Error must name `must_name` (the input file) when that is given.
template <typename F>
void Expect(F&& f, const std::string& must_name) {
  try {
    f();
  } catch (const imuconv::Error& e) {
    const std::string msg = e.what();
    if (msg.empty()) InputFile::Finding("an empty error message");
    if (!must_name.empty() && msg.find(must_name) == std::string::npos)
      InputFile::Finding("an error that does not name the file " + must_name + ": " + msg);
  } catch (const std::exception& e) {
    InputFile::Finding(std::string("an exception that is not imuconv::Error: ") + e.what());
  } catch (...) {
    InputFile::Finding("an exception of unknown type");
  }
}

}  // namespace imuconv::fuzz
