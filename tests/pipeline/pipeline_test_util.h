// Helpers for the pipeline and CLI tests: temporary directories, file writing, running the
// built binary, and the "every matrix carries its chart" check of output documents.
#pragma once

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>

#include "imuconv/pipeline/errors.h"
#include "text_contains.h"

namespace imuconv::test {

namespace fs = std::filesystem;

inline std::string SourcePath(const std::string& rel) {
  return std::string(IMUCONV_SOURCE_DIR) + "/" + rel;
}
inline std::string Binary() { return std::string(IMUCONV_BINARY_DIR) + "/bin/imuconv"; }

/// A fresh directory under the system temp dir, removed with its contents at scope exit.
class TempDir {
 public:
  TempDir() {
    std::random_device rd;
    const auto stamp = std::chrono::steady_clock::now().time_since_epoch().count();
    path_ = fs::temp_directory_path() /
            ("imuconv_test_" + std::to_string(stamp) + "_" + std::to_string(rd()));
    fs::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  std::string path() const { return path_.string(); }
  std::string file(const std::string& name) const { return (path_ / name).string(); }
  /// Writes `text` to name and returns the full path.
  std::string write(const std::string& name, const std::string& text) const {
    std::ofstream(file(name), std::ios::binary) << text;
    return file(name);
  }
  std::size_t entries() const {
    std::size_t n = 0;
    for ([[maybe_unused]] const auto& e : fs::directory_iterator(path_)) ++n;
    return n;
  }

 private:
  fs::path path_;
};

inline std::string ReadText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

inline std::string ShellQuote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

struct CommandResult {
  int exit_code = -1;
  std::string out, err;
};

/// Runs the built imuconv with `args` (already shell-quoted where needed), capturing
/// stdout and stderr separately. IMUCONV_PLUGIN_PATH is cleared so the user's environment
/// cannot change the results.
inline CommandResult RunImuconv(const std::string& args, const TempDir& tmp) {
  const std::string out = tmp.file(".stdout"), err = tmp.file(".stderr");
  const std::string cmd = "env -u IMUCONV_PLUGIN_PATH " + ShellQuote(Binary()) + " " + args +
                          " > " + ShellQuote(out) + " 2> " + ShellQuote(err);
  const int status = std::system(cmd.c_str());
  CommandResult r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = ReadText(out);
  r.err = ReadText(err);
  fs::remove(out);
  fs::remove(err);
  return r;
}

/// A CSV IMU's "columns" map: time in the column named `time_column`, each channel in the
/// column of its own name (wx, wy, wz, ax, ay, az).
inline nlohmann::json CsvColumnsNamedByChannel(const std::string& time_column) {
  return {{"t", time_column}, {"wx", "wx"}, {"wy", "wy"}, {"wz", "wz"},
          {"ax", "ax"},       {"ay", "ay"}, {"az", "az"}};
}

/// The `imu` of a pipeline reading a generic CSV: one header row, times in `time_unit` with origin
/// 0 in the column `time_column`, the channels in columns named wx, wy, wz, ax, ay, az (in any
/// order), separated by `delimiter` (the reader's default, ",", is not written).
inline nlohmann::json CsvImuFromTimeZero(const std::string& path, const std::string& time_unit,
                                         const std::string& time_column,
                                         const std::string& delimiter = ",") {
  nlohmann::json imu = {{"format", "csv"},  {"path", path},
                        {"header_rows", 1}, {"time_unit", time_unit},
                        {"time_origin", 0}, {"columns", CsvColumnsNamedByChannel(time_column)}};
  if (delimiter != ",") imu["delimiter"] = delimiter;
  return imu;
}

/// The output of the task named `name` in a run's document (its "tasks" list).
inline const nlohmann::json& TaskOutput(const nlohmann::json& out, const std::string& name) {
  for (const auto& t : out.at("tasks"))
    if (t.at("name") == name) return t;
  throw std::runtime_error("no task " + name);
}

/// Runs `imuconv COMMAND ARGS --json` and parses what it prints; a run that does not exit 0 is
/// a test failure (its stderr shown) and gives null.
inline nlohmann::json RunImuconvJson(const std::string& command, const std::string& args,
                                     const TempDir& tmp) {
  const CommandResult r = RunImuconv(command + " " + args + " --json", tmp);
  EXPECT_EQ(r.exit_code, 0) << command << " " << args << "\n" << r.err;
  return r.exit_code == 0 ? nlohmann::json::parse(r.out) : nlohmann::json();
}

/// Checks that every matrix in an output document names its chart(s) and block order, and
/// that its size matches the blocks: {"convention","blocks","matrix"} (3*blocks square) or
/// {"rows":{..},"cols":{..},"matrix"}. Returns the number of matrices seen.
inline std::size_t CheckMatricesLabelled(const nlohmann::json& j, const std::string& ptr = "") {
  std::size_t n = 0;
  if (j.is_object()) {
    if (j.contains("matrix")) {
      ++n;
      const auto& m = j["matrix"];
      EXPECT_TRUE(m.is_array() && !m.empty()) << ptr;
      std::size_t rows = 0, cols = 0;
      if (j.contains("rows")) {
        EXPECT_TRUE(j["rows"].contains("convention") && j["rows"].contains("blocks")) << ptr;
        EXPECT_TRUE(j["cols"].contains("convention") && j["cols"].contains("blocks")) << ptr;
        rows = 3 * j["rows"]["blocks"].size();
        cols = 3 * j["cols"]["blocks"].size();
      } else {
        EXPECT_TRUE(j.contains("convention") && j["convention"].is_string())
            << ptr << " has no convention";
        EXPECT_TRUE(j.contains("blocks") && j["blocks"].size() == 5)
            << ptr << " has no block order";
        rows = cols = 15;
      }
      EXPECT_EQ(m.size(), rows) << ptr;
      for (const auto& r : m) EXPECT_EQ(r.size(), cols) << ptr;
    }
    for (auto it = j.begin(); it != j.end(); ++it)
      if (it.key() != "matrix") n += CheckMatricesLabelled(it.value(), ptr + "/" + it.key());
  } else if (j.is_array()) {
    for (std::size_t i = 0; i < j.size(); ++i)
      n += CheckMatricesLabelled(j[i], ptr + "/" + std::to_string(i));
  }
  return n;
}

/// The message of the exception `f` throws, or "" if it throws none.
template <typename E = std::exception>
std::string MessageOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const E& e) {
    return e.what();
  }
  return "";
}

}  // namespace imuconv::test
