// Which keys a reference case must have, and the standard values of those a command that does
// not use them may leave out (tests/data/reference/FORMAT.md): every missing key is named at
// once, not one per run.
#include <array>

#include "imuconv/status.h"
#include "refcase.h"

namespace imuconv::refcase {
namespace {

using nlohmann::json;

/// A key of the case by its JSON pointer's parts (`parent` empty for a top-level key), and the
/// value it takes when a command may leave it out.
struct CaseKey {
  const char* parent;
  const char* key;
  bool needed_by_every_command;  ///< the samples and the densities: no standard value
  json standard;                 ///< the value used when left out (see FORMAT.md)
};

json ZeroMatrix15() {
  json rows = json::array();
  for (int i = 0; i < 15; ++i) rows.push_back(json(std::vector<double>(15, 0.0)));
  return rows;
}

const std::vector<CaseKey>& Keys() {
  static const std::vector<CaseKey> keys = {
      {"", "imu", true, nullptr},
      {"noise", "gyro_noise_density", true, nullptr},
      {"noise", "accel_noise_density", true, nullptr},
      {"noise", "gyro_random_walk", true, nullptr},
      {"noise", "accel_random_walk", true, nullptr},
      // Gravity 9.81 m/s^2 along -z of the world frame (FORMAT.md's convention, z up).
      {"", "gravity", false, json::array({0.0, 0.0, -9.81})},
      // The identity start state: at the origin, at rest, unrotated; zero bias estimate.
      {"state_s", "q_wxyz", false, json::array({1.0, 0.0, 0.0, 0.0})},
      {"state_s", "p", false, json::array({0.0, 0.0, 0.0})},
      {"state_s", "v", false, json::array({0.0, 0.0, 0.0})},
      {"state_s", "bg", false, json::array({0.0, 0.0, 0.0})},
      {"state_s", "ba", false, json::array({0.0, 0.0, 0.0})},
      // A start state known exactly, no end perturbation and no bias change.
      {"cov_s_left", "matrix", false, ZeroMatrix15()},
      {"", "end_perturbation", false, json(std::vector<double>(15, 0.0))},
      {"bias_delta", "bg", false, json::array({0.0, 0.0, 0.0})},
      {"bias_delta", "ba", false, json::array({0.0, 0.0, 0.0})},
  };
  return keys;
}

std::string Pointer(const CaseKey& k) {
  return std::string(*k.parent ? "/" : "") + k.parent + "/" + k.key;
}

}  // namespace

Case ParseCase(const json& case_json, CaseKeys keys, std::vector<std::string>* defaulted) {
  if (!case_json.is_object())
    return ParseCase(case_json);  // refused there, as "expected a JSON object"
  json filled = case_json;
  std::string missing;
  for (const CaseKey& k : Keys()) {
    const bool has_parent = !*k.parent || filled.contains(k.parent);
    if (has_parent && *k.parent && !filled.at(k.parent).is_object())
      continue;  // refused by ParseCase
    if (has_parent && (*k.parent ? filled.at(k.parent) : filled).contains(k.key)) continue;
    if (k.needed_by_every_command || keys == CaseKeys::all_required) {
      missing += (missing.empty() ? "" : ", ") + Pointer(k);
    } else {
      json& parent =
          *k.parent ? filled[k.parent] : filled;  // an absent parent becomes an object here
      parent[k.key] = k.standard;
      if (defaulted) defaulted->push_back(Pointer(k));
    }
  }
  if (!missing.empty())
    throw Error(missing + ": missing (" +
                (keys == CaseKeys::all_required ? "every key"
                                                : "the samples and the four noise densities") +
                " of tests/data/reference/FORMAT.md must be given)");
  return ParseCase(filled);
}

}  // namespace imuconv::refcase
