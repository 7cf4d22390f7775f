// The plugins a pipeline's tasks use, for the provenance record of the output (internal).
#pragma once

#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "imuconv/pipeline/measurement.h"
#include "imuconv/registry.h"

namespace imuconv::pipeline {

struct PipelineSpec;
struct CovSpec;

/// What the tasks name or imply, collected (Task::plugins_used); ids the registry does not
/// know are left out (they are reported as errors before anything runs).
class PluginUse {
 public:
  explicit PluginUse(const Registry& reg) : reg_(reg) {}
  void add(PluginKind kind, const std::string& id);
  void state(const std::string& id) { add(PluginKind::StateConvention, id); }
  /// An increment convention, with its bias-Jacobian chart (expressing a measurement in it
  /// uses both).
  void increment(const std::string& id);
  /// A propagator, with its native state chart.
  void propagator(const std::string& id);
  /// The chart a given covariance names, as a state convention.
  void state_cov(const CovSpec& cov);
  /// Some task holds preintegrated measurements (in preint_reference).
  void measurements() { measurements_ = true; }
  const Registry& registry() const { return reg_; }
  /// Sorted by kind, then id, with each kind's reference chart when a convention of that
  /// kind is used (every conversion goes through it).
  std::vector<const PluginInfo*> list();

 private:
  const Registry& reg_;
  std::set<std::pair<PluginKind, std::string>> used_;
  bool measurements_ = false;
};

/// Every plugin a task uses, named or implied: propagators and preintegrators with their
/// native charts, the state and increment conventions named by tasks, matrices and
/// measurement files (`files`), and each kind's reference chart.
std::vector<const PluginInfo*> PluginsUsed(
    const PipelineSpec& s, const Registry& reg,
    const std::map<std::string, std::vector<MeasRecord>>& files);

}  // namespace imuconv::pipeline
