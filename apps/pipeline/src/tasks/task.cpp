// The Task interface's defaults (task.h).
#include "task.h"

namespace imuconv::pipeline {

void Task::references(const std::function<void(const std::string& name, const std::string& pointer)>& f) const {
  if (const MeasurementsSpec* m = measurements(); m && !m->task.empty()) f(m->task, m->pointer);
}

KeptRecords Task::kept_records(const std::function<std::size_t(const MeasurementsSpec&)>&) const { return {}; }

void Task::check_times(const RunContext&, Checker&) const {}

}  // namespace imuconv::pipeline
