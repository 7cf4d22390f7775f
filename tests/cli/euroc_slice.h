// The bundled 20 s EuRoC V1_01 slice (examples/data) the CLI tests run on: its IMU and ground
// truth files, the datasheet's noise, a copy of both files into a test's own directory (data/,
// for tests that change or shard what they read) and a pipeline over that copy.
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "../pipeline/pipeline_test_util.h"

namespace imuconv::test {

inline const std::string kEurocSliceImu = SourcePath("examples/data/V1_01_easy_imu0_slice.csv");
inline const std::string kEurocSliceGroundTruth =
    SourcePath("examples/data/V1_01_easy_groundtruth_vicon2gt_slice.csv");

/// Copies both files into `tmp`/data/ under their own names.
inline void CopyEurocSlice(const TempDir& tmp) {
  std::filesystem::create_directories(tmp.file("data"));
  for (const std::string& f : {kEurocSliceImu, kEurocSliceGroundTruth})
    std::filesystem::copy_file(f, tmp.file("data/" + std::filesystem::path(f).filename().string()));
}

/// The EuRoC datasheet densities (those of examples/euroc_v1_01_keyframes.json and of
/// tests/data/kalibr/euroc_imu.yaml).
inline const nlohmann::json kEurocNoise = {{"gyro_noise_density", 1.6968e-04},
                                           {"accel_noise_density", 2.0e-3},
                                           {"gyro_random_walk", 1.9393e-05},
                                           {"accel_random_walk", 3.0e-3}};

/// A pipeline running `tasks` on the copy CopyEurocSlice makes (paths relative to the pipeline
/// written beside data/), with the datasheet noise and gravity (0, 0, gravity_z).
inline nlohmann::json EurocSlicePipeline(const nlohmann::json& tasks, double gravity_z = -9.81) {
  return {{"gravity", {0.0, 0.0, gravity_z}},
          {"noise", kEurocNoise},
          {"imu", {{"format", "euroc"}, {"path", "data/V1_01_easy_imu0_slice.csv"}}},
          {"ground_truth",
           {{"format", "euroc"}, {"path", "data/V1_01_easy_groundtruth_vicon2gt_slice.csv"}}},
          {"tasks", tasks}};
}

/// A pipeline for nees --pipeline: samples from the source `imu` with the slice's own ground
/// truth (absolute path) and the datasheet noise. A pipeline has tasks and nees runs none of
/// them: the one task here is never run.
inline nlohmann::json NeesPipeline(const nlohmann::json& imu) {
  return {{"noise", kEurocNoise},
          {"imu", imu},
          {"ground_truth", {{"format", "euroc"}, {"path", kEurocSliceGroundTruth}}},
          {"tasks", nlohmann::json::array({{{"type", "propagate"},
                                            {"name", "unused"},
                                            {"propagator", "euler"},
                                            {"start", {{"state", "ground_truth"}}},
                                            {"interval", {{"t_start", 0.0}, {"t_end", 0.5}}}}})}};
}

}  // namespace imuconv::test
