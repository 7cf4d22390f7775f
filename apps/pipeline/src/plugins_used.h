// The plugins a pipeline's tasks use, for the provenance record of the output (internal).
#pragma once

#include <map>
#include <string>
#include <vector>

#include "imuconv/registry.h"
#include "measurement_file.h"
#include "spec.h"

namespace imuconv::pipeline {

/// Every plugin a task uses, named or implied: propagators and preintegrators with their
/// native charts, the state and increment conventions named by tasks, matrices and
/// measurement files (`files`), and each kind's reference chart when a convention of that kind
/// is used (every conversion goes through it). Sorted by kind, then id; ids the registry
/// does not know are left out (they are reported as errors before anything runs).
std::vector<const PluginInfo*> PluginsUsed(const PipelineSpec& s, const Registry& reg,
                                           const std::map<std::string, std::vector<MeasRecord>>& files);

}  // namespace imuconv::pipeline
