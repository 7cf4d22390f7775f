// The parsed form of a pipeline document (internal to imuconv_pipeline): the top-level keys,
// the IMU and ground-truth sources, and the tasks (each behind the Task interface of
// tasks/task.h, a layer above: the spec only holds them, so Task is declared here and the
// spec is destroyed where it is complete, tasks/task.cpp). The document is read into it by
// ParseSpec (run/parse.h), which knows the task kinds.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "../forms/task_common.h"
#include "imuconv/pipeline/imu_reader.h"
#include "imuconv/pipeline/json_io.h"

namespace imuconv::pipeline {

class Task;

struct ImuSourceSpec {
  enum class Format { Euroc, Csv, Inline } format = Format::Euroc;
  std::string path;                       // resolved
  std::optional<std::int64_t> origin_ns;  // euroc
  CsvFormat csv;                          // csv (and time_unit/time_origin for inline)
  std::vector<ImuSample> inline_raw;      // inline: t in time units (not yet relative)
  std::vector<TimeValue> inline_t;
  std::vector<std::size_t> inline_index;  // inline: the index of each kept sample in "samples"
  TimingPolicy timing;                    // max_gap_factor, allow_gaps
  std::string pointer;
};

struct GroundTruthSpec {
  std::string path;              // resolved
  std::string format = "euroc";  ///< "euroc" (full state), "euroc_pose" or "tum" (poses only)
  SensorInBody sensor;           ///< T_BS of a pose file's sensor (identity by default)
  TimingPolicy timing;
  std::string pointer;
};

struct PipelineSpec {
  std::string file, base_dir;
  OmitSpec omit;
  std::string description;
  std::vector<std::string> plugin_dirs;
  bool allow_plugin_override = false;
  /// Intervals holding no IMU sample (keyframes finer than the samples) are meant: see
  /// RunContext::check_intervals_hold_samples.
  bool allow_empty_intervals = false;
  std::optional<std::string> output;
  Vec3 gravity = Vec3(0.0, 0.0, -9.81);
  ImuNoise noise;
  bool has_noise =
      false;  ///< the document gives "noise" (required only by tasks that integrate samples)
  std::string noise_file;  ///< the Kalibr imu.yaml the noise was read from (resolved), if any
  std::optional<ImuSourceSpec> imu;
  std::optional<GroundTruthSpec> gt;
  std::vector<std::unique_ptr<const Task>> tasks;

  PipelineSpec();  // tasks/task.cpp, where Task is complete
  ~PipelineSpec();
  PipelineSpec(const PipelineSpec&) = delete;
  PipelineSpec& operator=(const PipelineSpec&) = delete;
};

}  // namespace imuconv::pipeline
