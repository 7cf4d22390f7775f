// A task kind behind one small interface: each kind is one file in this directory holding its
// spec, parse, checks, run and write, and one line in the list of kinds (kinds.cpp) that
// maps "type" to its parser. The stages (run.cpp) know no task kind: they ask each task
// what it needs (IMU range, measurements, earlier tasks), let it check itself against the
// registry and the data, then run it.
#pragma once

#include <cstddef>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "../forms/intervals.h"
#include "../forms/task_common.h"
#include "imuconv/pipeline/json_check.h"
#include "imuconv/pipeline/json_writer.h"

namespace imuconv::pipeline {

class RunContext;
class PluginUse;
struct TaskResult;

/// The per-interval records a task keeps when a later task names it (an estimate, made before
/// any task runs, against RunOptions::max_kept_bytes).
struct KeptRecords {
  std::size_t count = 0;
  std::size_t bytes_each = 0;
  const char* what = "";  ///< "measurement", "step", ... for the message
};

class Task {
 public:
  virtual ~Task() = default;

  /// The header of every task.
  std::string type, name, description;
  std::string pointer;  ///< /tasks/N

  /// The interval or keyframes it integrates IMU samples over, if any: only the range the
  /// tasks span is read into memory. A task that integrates samples needs the noise too.
  virtual const IntervalsSpec* intervals() const { return nullptr; }
  /// The measurements it reads (an earlier task's or a file's), if any.
  virtual const MeasurementsSpec* measurements() const { return nullptr; }
  /// A file it reads itself rather than through measurements() (the check task's declared
  /// measurements), if any: an output must not be it (Pipeline::input_files).
  virtual const std::string* input_file() const { return nullptr; }
  /// Calls f(name, pointer) for each earlier task whose results it uses (by default the task
  /// its measurements come from): those tasks keep their results.
  virtual void references(
      const std::function<void(const std::string& name, const std::string& pointer)>& f) const;
  /// What it keeps when a later task names it; `count_of` says how many measurements a
  /// measurements source holds.
  virtual KeptRecords kept_records(
      const std::function<std::size_t(const MeasurementsSpec&)>& count_of) const;
  /// The plugins it uses, for the output's provenance list.
  virtual void plugins_used(PluginUse& use) const = 0;

  /// Stage "check ids": plugin ids and matrix charts against the registry, reported into
  /// `c`. Plugins it runs are resolved here, once, into the context.
  virtual void check_plugins(RunContext& ctx, Checker& c) const = 0;
  /// Stage "check times": its times against the loaded IMU data and ground truth.
  virtual void check_times(const RunContext& ctx, Checker& c) const;
  /// Stage "execute and stream": computes and writes its keys into the open task object of
  /// `w`; what a later task may use goes into `result` (kept only when one names it).
  virtual void run(RunContext& ctx, JsonWriter& w, TaskResult& result) const = 0;
};

/// Reads a task of one kind from its object (the header keys are read by the caller, and
/// `type` already checked). Every problem is reported into the context's checker; the task
/// is returned all the same (the caller throws once the whole document is read).
using TaskParser = std::unique_ptr<Task> (*)(const ParseContext& ctx, const Node& n);

struct TaskKind {
  const char* type;
  TaskParser parse;
};

/// Every task kind, in the schema's order (kinds.cpp).
const std::vector<TaskKind>& TaskKinds();

}  // namespace imuconv::pipeline
