#include "imuconv/optimize/optimize_input.h"

#include <sys/stat.h>

#include <fstream>
#include <sstream>

#include "imuconv/pipeline/errors.h"
#include "imuconv/pipeline/imu_plausibility.h"
#include "imuconv/pipeline/pipeline.h"
#include "imuconv/pipeline/pipeline_data.h"

namespace imuconv::optimize {

namespace {

// A sniff reads at most this many lines looking for the first data row: a header block is a
// line or two, and a file whose first data row is further down is read as "euroc" and judged by
// its reader.
constexpr int kSniffLines = 64;

std::size_t CountFields(const std::string& line, bool commas) {
  if (commas) {
    std::size_t n = 1;
    for (const char c : line) n += c == ',' ? 1 : 0;
    return n;
  }
  std::istringstream in(line);
  std::string field;
  std::size_t n = 0;
  while (in >> field) ++n;
  return n;
}

const char* kVicon0Warning =
    ": EuRoC vicon0 poses are the Vicon marker's; they are used as the IMU's (no T_BS is "
    "applied), so the estimate carries the marker's lever arm";

// The poses' rotations against the gyro (a quaternion order, a sequence or a time axis mistaken).
void AddPoseGyroWarnings(Input& in, const std::string& poses_name) {
  for (auto& w : pipeline::PoseGyroWarnings(in.imu.samples, in.poses, poses_name))
    in.warnings.push_back(std::move(w));
}

}  // namespace

std::string PoseFileFormat(const std::string& path) {
  // Only a regular file is opened here (a FIFO would block, and be consumed); anything else goes
  // to the reader, which refuses it with its own message.
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0 || !S_ISREG(st.st_mode)) return "euroc";
  std::ifstream in(path);
  std::string line;
  for (int i = 0; i < kSniffLines && std::getline(in, line); ++i) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const auto first = line.find_first_not_of(" \t");
    if (first == std::string::npos || line[first] == '#') continue;
    const bool commas = line.find(',') != std::string::npos;
    const std::size_t n = CountFields(line, commas);
    if (commas && n == 8) return "euroc_pose";
    if (!commas && n == 8) return "tum";
    return "euroc";
  }
  return "euroc";
}

Input ReadFileInput(const std::string& imu_path, const std::string& poses_path) {
  Input in;
  in.imu = pipeline::ReadEurocImu(imu_path);
  in.warnings = in.imu.warnings;
  const std::string format = PoseFileFormat(poses_path);
  if (format == "euroc")
    in.poses = pipeline::ReadEurocGroundTruth(poses_path, *in.imu.origin);
  else
    in.poses = pipeline::ReadPoseGroundTruth(poses_path, format, *in.imu.origin);
  if (format == "euroc_pose") in.warnings.push_back(poses_path + kVicon0Warning);
  AddPoseGyroWarnings(in, poses_path);
  return in;
}

Input ReadPipelineInput(const std::string& pipeline_path) {
  const pipeline::Pipeline p = pipeline::Pipeline::Load(pipeline_path);
  if (!p.has_ground_truth())
    throw pipeline::ConfigError(
        p.file(), {{"/ground_truth",
                    "required key is missing: optimize measures each keyframe's pose there"}});
  Input in;
  in.imu = pipeline::ReadPipelineImu(p);
  in.warnings = in.imu.warnings;
  in.poses = *pipeline::ReadPipelineGroundTruth(p, in.imu);
  in.gravity = pipeline::PipelineGravity(p);
  in.noise = pipeline::PipelineNoiseIfGiven(p);
  if (in.poses.format == "euroc_pose")
    in.warnings.push_back(p.file() + ": /ground_truth" + kVicon0Warning);
  AddPoseGyroWarnings(in, p.file() + ": /ground_truth");
  return in;
}

}  // namespace imuconv::optimize
