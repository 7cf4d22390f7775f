// The Task interface's defaults (task.h), and the parsed document's construction and
// destruction: spec/pipeline_spec.h holds its tasks by pointer to a Task it only declares
// (the spec layer is below the tasks), so its members are created and destroyed here, where
// Task is complete.
#include "task.h"

#include "../spec/pipeline_spec.h"

namespace imuconv::pipeline {

void Task::references(
    const std::function<void(const std::string& name, const std::string& pointer)>& f) const {
  if (const MeasurementsSpec* m = measurements(); m && !m->task.empty()) f(m->task, m->pointer);
}

KeptRecords Task::kept_records(const std::function<std::size_t(const MeasurementsSpec&)>&) const {
  return {};
}

void Task::check_times(const RunContext&, Checker&) const {}

PipelineSpec::PipelineSpec() = default;
PipelineSpec::~PipelineSpec() = default;

}  // namespace imuconv::pipeline
