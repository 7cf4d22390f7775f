// JSON forms of states, noise and matrices, as json values and read from a Node (used by the
// conversion and refcase commands too). Implemented one form per file in src/forms/ (state,
// noise, chart_matrix), beside each form's streaming writer.
//
//   state:  {"p":[3], "q_wxyz":[4] (Hamilton, body to world), "v":[3], "bg":[3], "ba":[3]}
//   noise:  {"gyro_noise_density", "accel_noise_density", "gyro_random_walk", "accel_random_walk"}
//   matrix: a row-major array of rows. Every matrix imuconv writes carries its chart:
//     {"convention": ID, "blocks": [5 labels], "matrix": [[...]]}              (one chart)
//     {"rows": {"convention", "blocks"}, "cols": {"convention", "blocks"}, "matrix"} (two)
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "imuconv/pipeline/json_check.h"
#include "imuconv/pipeline/matrix_rows.h"  // MatrixToJson
#include "imuconv/pipeline/output_file.h"  // OutputFile, WriteFileAtomically (they lived here)
#include "imuconv/registry.h"
#include "imuconv/types.h"

namespace imuconv::pipeline {

json Vec3ToJson(const Vec3& v);
json StateToJson(const ImuState& x);
json NoiseToJson(const ImuNoise& n);
/// {"rows": {...}, "cols": {...}, "matrix": m}.
json MixedMatrixToJson(const Eigen::MatrixXd& m, const std::string& row_convention,
                       const std::vector<std::string>& row_blocks,
                       const std::string& col_convention,
                       const std::vector<std::string>& col_blocks);

/// Block labels of a registered convention, e.g. {"theta","p","v","ba","bg"}.
std::vector<std::string> Blocks(const Registry& reg, PluginKind kind, const std::string& id);

/// Reads a state object (bg and ba default to zero); the quaternion must have unit norm
/// within 1e-6 and is normalised.
[[nodiscard]] std::optional<ImuState> StateFromJson(const Node& n);
[[nodiscard]] std::optional<ImuNoise> NoiseFromJson(const Node& n);
/// A pipeline's /noise in either of its forms: the four densities (NoiseFromJson), or
/// {"kalibr": "imu.yaml"}, that Kalibr file read now (ReadKalibrImuYaml), a relative path
/// resolved against `base_dir`, the directory of the document holding `n`, as every path in a
/// pipeline is. The file's problems are reported at n's "kalibr" pointer. `kalibr_file`, when
/// given, receives the resolved path of the file read. The one reader of the form: the
/// pipeline's /noise and a --noise file (nees, optimize) both come here.
[[nodiscard]] std::optional<ImuNoise> NoiseFormFromJson(const Node& n, const std::string& base_dir,
                                                        std::string* kalibr_file = nullptr);

/// A 15x15 matrix given as an array of rows, {"diagonal": [15]}, {"sigma": [15]} (standard
/// deviations) or {"convention": id, "blocks": [...], "matrix": [[...]]}. When a convention
/// is written it is returned in `convention` (the caller converts or checks it).
struct Matrix15In {
  Mat15 m = Mat15::Zero();
  std::optional<std::string> convention;
  std::optional<std::vector<std::string>> blocks;
  std::string pointer;
};
[[nodiscard]] std::optional<Matrix15In> Matrix15FromJson(const Node& n);

/// JSON text with objects indented and every array of numbers (vector, matrix row) on one line.
std::string PrettyJson(const json& j);

/// Reads a state file (a JSON state object) with the checks of StateFromJson; throws
/// ConfigError naming the file and pointer.
[[nodiscard]] ImuState ReadStateFile(const std::string& path);
/// Reads an increment file (the form of a measurement's "delta": q_wxyz and/or R, dp, dv,
/// dbg, dba) with every check of the pipeline's one increment reader; throws ConfigError
/// naming the file and pointer.
[[nodiscard]] PreintIncrement ReadIncrementFile(const std::string& path);
/// Reads a 15x15 matrix file in any Matrix15FromJson form. With `covariance` it must be one
/// (symmetric and positive semi-definite within 1e-9 of its largest variance): nothing is
/// repaired. Throws ConfigError naming the file and pointer.
[[nodiscard]] Matrix15In ReadMatrixFile(const std::string& path, bool covariance);

}  // namespace imuconv::pipeline
