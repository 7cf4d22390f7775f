// The EuRoC slice's ground truth with its quaternions in the other component order, and a
// command's run on it against its run on the slice's own (pipeline::PoseGyroWarnings): the CLI
// and optimize tests write the file into their own directory.
#pragma once

#include <gtest/gtest.h>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "euroc_slice.h"
#include "imuconv_test.h"
#include "text_contains.h"

namespace imuconv::test {

/// What follows "SOURCE" in the warning.
inline const std::string kPosesDisagree = ": the poses' rotations disagree with the gyro: over ";

// The slice's ground truth with each row's qw,qx,qy,qz (fields 4..7) replaced by qx,qy,qz,qw:
// a file of x,y,z,w quaternions read as w,x,y,z.
inline std::string ReorderedGroundTruth(const TempDir& tmp, const std::string& name) {
  std::ifstream in(kEurocSliceGroundTruth);
  std::string line, text;
  while (std::getline(in, line)) {
    if (!line.empty() && line[0] != '#') {
      std::vector<std::string> f;
      std::stringstream s(line);
      for (std::string x; std::getline(s, x, ',');) f.push_back(x);
      EXPECT_EQ(f.size(), 17u) << line;
      const std::string qw = f[4];
      f[4] = f[5], f[5] = f[6], f[6] = f[7], f[7] = qw;
      line = f[0];
      for (std::size_t k = 1; k < f.size(); ++k) line += "," + f[k];
    }
    text += line + "\n";
  }
  return tmp.write(name, text);
}

/// Runs `command_before + POSES + command_after` (a command with --json) on the slice's ground
/// truth, then on its reordered copy: both exit 0 (a warning, never a refusal); the first has no
/// "warnings", the second exactly one, naming the copy, with the likely cause, also on stderr.
inline void ExpectWarningOnReorderedPosesOnly(const TempDir& tmp, const std::string& command_before,
                                              const std::string& command_after) {
  const std::string reordered = ReorderedGroundTruth(tmp, "poses_xyzw.csv");
  for (const std::string& poses : {kEurocSliceGroundTruth, reordered}) {
    const CommandResult r = RunImuconv(command_before + ShellQuote(poses) + command_after, tmp);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const nlohmann::json out = nlohmann::json::parse(r.out);
    if (poses == kEurocSliceGroundTruth) {
      EXPECT_FALSE(out.contains("warnings")) << out["warnings"];
      EXPECT_FALSE(Has(r.err, "warning")) << r.err;
      continue;
    }
    ASSERT_TRUE(out.contains("warnings")) << r.out;
    ASSERT_EQ(out["warnings"].size(), 1u) << out["warnings"];
    const std::string w = out["warnings"][0];
    EXPECT_TRUE(Has(w, poses + kPosesDisagree)) << w;
    EXPECT_TRUE(Has(w, "check the quaternion order (w,x,y,z or x,y,z,w)")) << w;
    EXPECT_TRUE(Has(r.err, "imuconv: warning: " + w)) << r.err;
  }
}

}  // namespace imuconv::test
