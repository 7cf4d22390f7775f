#include "imuconv/pipeline/kalibr_yaml.h"

#include <yaml-cpp/depthguard.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <set>
#include <string>
#include <vector>

#include "../io/input_file.h"
#include "imuconv/pipeline/errors.h"
#include "imuconv/printable.h"

namespace imuconv::pipeline::data {
namespace {

std::size_t LineOf(const YAML::Node& n) { return static_cast<std::size_t>(n.Mark().line + 1); }

/// The mapping that holds the keys: the document, or its one imuN entry.
YAML::Node ImuMapping(const std::string& path, const YAML::Node& doc) {
  if (!doc.IsMap())
    throw ReadError(path, doc.IsDefined() ? LineOf(doc) : 0,
                    "expected a YAML mapping of Kalibr IMU keys");
  if (doc["gyroscope_noise_density"] || doc["accelerometer_noise_density"]) return doc;
  std::vector<std::string> imus;
  YAML::Node found;
  for (const auto& kv : doc) {
    const std::string key = kv.first.IsScalar() ? kv.first.Scalar() : "";
    if (key.size() > 3 && key.compare(0, 3, "imu") == 0 && kv.second.IsMap()) {
      imus.push_back(key);
      found = kv.second;
    }
  }
  if (imus.size() == 1) return found;
  if (imus.empty())
    throw ReadError(path, 0,
                    "no Kalibr IMU keys (gyroscope_noise_density, accelerometer_noise_density, "
                    "gyroscope_random_walk, "
                    "accelerometer_random_walk), at the top level or under one imu0 entry");
  std::string list;
  for (const auto& k : imus) list += (list.empty() ? "" : ", ") + Printable(k);
  throw ReadError(path, 0, "several IMUs (" + list + "): give a file with one IMU's noise");
}

/// Refuses a mapping that gives one key twice, anywhere in the document: yaml-cpp keeps both
/// and a lookup finds the first, so the second would be ignored in silence (JSON duplicates are
/// refused too, json_parse.cpp). The walk uses its own stack and a bound on the values it visits,
/// since YAML aliases can make a small file expand exponentially.
void RefuseDuplicateKeys(const std::string& path, const YAML::Node& doc) {
  // A 64 KiB file holds at most about 32 000 values written out; more can only come from aliases.
  constexpr std::size_t kMaxVisits = std::size_t{1} << 17;
  std::vector<YAML::Node> todo{doc};
  std::size_t visits = 0;
  while (!todo.empty()) {
    const YAML::Node n = todo.back();
    todo.pop_back();
    if (++visits > kMaxVisits)
      throw ReadError(path, 0,
                      "expands to more than " + std::to_string(kMaxVisits) +
                          " values (YAML aliases?), more than any Kalibr IMU file holds");
    if (n.IsMap()) {
      std::set<std::string> seen;
      for (const auto& kv : n) {
        if (kv.first.IsScalar() && !seen.insert(kv.first.Scalar()).second)
          throw ReadError(path, LineOf(kv.first),
                          "duplicate key " + Quoted(kv.first.Scalar()) +
                              " (the first value would silently win; give each key once)");
        todo.push_back(kv.second);
      }
    } else if (n.IsSequence()) {
      for (const auto& e : n) todo.push_back(e);
    }
  }
}

double NonNegative(const std::string& path, const YAML::Node& map, const char* key, bool required,
                   double fallback) {
  const YAML::Node v = map[key];
  if (!v) {
    if (!required) return fallback;
    throw ReadError(path, LineOf(map), std::string(key) + ": required key is missing");
  }
  double x = 0.0;
  if (!v.IsScalar() || !YAML::convert<double>::decode(v, x))
    throw ReadError(path, LineOf(v), std::string(key) + ": expected a number");
  if (!std::isfinite(x) || x < 0.0)
    throw ReadError(
        path, LineOf(v),
        std::string(key) + ": expected a finite non-negative number, found " + Quoted(v.Scalar()));
  return x;
}

}  // namespace

ImuNoise ReadKalibrImuYaml(const std::string& path) {
  const std::string text = ReadWholeFile(
      path, kMaxKalibrYamlBytes, "64 KiB",
      ", the largest Kalibr IMU file imuconv reads (a real one is a few hundred bytes)");
  YAML::Node doc;
  try {
    doc = YAML::Load(text);
  } catch (const YAML::DeepRecursion& e) {
    // yaml-cpp's depth guard (its message says only "bad file").
    throw ReadError(path, static_cast<std::size_t>(e.mark.line + 1),
                    "not valid YAML: nested " + std::to_string(e.depth()) +
                        " levels deep, deeper than any IMU file");
  } catch (const YAML::Exception& e) {
    // yaml-cpp's own message, without its "yaml-cpp: error at line L, column C: " prefix.
    throw ReadError(path, e.mark.is_null() ? 0 : static_cast<std::size_t>(e.mark.line + 1),
                    "not valid YAML: " + Printable(e.msg));
  }
  RefuseDuplicateKeys(path, doc);
  const YAML::Node m = ImuMapping(path, doc);
  ImuNoise q;
  q.gyro_noise_density = NonNegative(path, m, "gyroscope_noise_density", true, 0.0);
  q.accel_noise_density = NonNegative(path, m, "accelerometer_noise_density", true, 0.0);
  q.gyro_random_walk = NonNegative(path, m, "gyroscope_random_walk", true, 0.0);
  q.accel_random_walk = NonNegative(path, m, "accelerometer_random_walk", true, 0.0);
  if (m["update_rate"] && !(NonNegative(path, m, "update_rate", false, 0.0) > 0.0))
    throw ReadError(path, LineOf(m["update_rate"]), "update_rate: expected a rate > 0 Hz");
  return q;
}

}  // namespace imuconv::pipeline::data
