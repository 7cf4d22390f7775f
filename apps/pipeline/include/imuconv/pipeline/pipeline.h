// JSON pipelines: an IMU source, noise, gravity and an ordered list of named tasks
// (propagate, preintegrate, propagate_by_preintegration, convert, residual, bias_update, check).
// The format is described by schemas/pipeline.schema.json and docs in examples/README.md.
//
// Loading validates the structure by hand and reports every problem with its JSON pointer
// (unknown keys included); running then checks plugin ids against the registry and times
// against the data (again with pointers) before any task runs, and produces one output
// JSON document. Nothing is written here: the caller writes the document (atomically).
//
// Inputs are checked, never repaired (covariances symmetric and positive semi-definite,
// unit quaternions, statements of one value that must agree, IMU and ground-truth gaps).
// Memory is bounded by the work asked: only the data range the tasks use is read into
// memory, and a task's per-interval results are kept only when a later task names it. The
// document records the file and version of every plugin the tasks used ("plugins").
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <iosfwd>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "imuconv/pipeline/json_check.h"
#include "imuconv/pipeline/result_arrays.h"
#include "imuconv/pipeline/run_options.h"
#include "imuconv/pipeline/text_sink.h"
#include "imuconv/registry.h"

namespace imuconv::pipeline {

struct PipelineSpec;  // the parsed document (apps/pipeline/src/spec/pipeline_spec.h)

class Pipeline {
 public:
  /// Reads and validates a pipeline file; relative paths in it are relative to its directory.
  /// Throws ConfigError (every issue, with pointers) or ReadError (file cannot be opened).
  static Pipeline Load(const std::string& path);
  /// The same from a parsed document; `file` names it in messages, `base_dir` resolves paths.
  static Pipeline FromJson(const json& doc, const std::string& file, const std::string& base_dir);

  Pipeline(Pipeline&&) noexcept;
  Pipeline& operator=(Pipeline&&) noexcept;
  ~Pipeline();

  const std::string& file() const;
  /// The pipeline's plugin_dirs, resolved against its directory.
  const std::vector<std::string>& plugin_dirs() const;
  /// The pipeline's "output" key, resolved against its directory.
  const std::optional<std::string>& output_path() const;
  /// Every file the pipeline reads: the pipeline itself, the Kalibr noise file, the IMU and
  /// ground-truth files and the measurement files, each once, as resolved paths. An output must be
  /// none of them.
  std::vector<std::string> input_files() const;
  /// The names of the tasks whose steps RunOptions::on_step receives (propagate_by_preintegration).
  std::vector<std::string> step_tasks() const;
  /// Whether the pipeline has a ground-truth source (its steps can be compared).
  bool has_ground_truth() const;
  const PipelineSpec& spec() const { return *spec_; }

 private:
  explicit Pipeline(std::unique_ptr<PipelineSpec> s);
  std::unique_ptr<PipelineSpec> spec_;
};

/// Runs and streams the output document (pretty-printed as PrettyJson lays it out; numbers in
/// the shortest form that reads back exactly) into `sink` while the tasks run, so that a large
/// document never has to be held in memory. The registry is loaded as by Run. On any error
/// the sink has received an incomplete document: write it to a temporary (OutputFile) and
/// discard it on failure.
void RunToText(const Pipeline& p, const RunOptions& options, const TextSink& sink);
void RunToText(const Pipeline& p, const Registry& reg, const RunOptions& options,
               const TextSink& sink);

/// Loads the registry from RunOptions::plugin_dirs, the pipeline's plugin_dirs and the
/// default search path, then runs. Throws ConfigError / ReadError / Error naming the file.
/// The document is RunToText's text, parsed.
json Run(const Pipeline& p, const RunOptions& options);
/// Runs with a given registry (plugin_dirs of the pipeline and options are then ignored).
json Run(const Pipeline& p, const Registry& reg, const RunOptions& options);

/// Runs the pipeline (as RunToText does, the registry loaded as RunToText loads it, or given)
/// and returns its output document's arrays and sidecar (result_arrays.h): the same, name for name
/// and bit for bit, as CollectResultArrays gives for the document's text, but collected from the
/// values the tasks write, without formatting them as text and reading them back. Holds what
/// CollectResultArrays holds (the numbers and the sidecar), never the document. `started` (may
/// be empty) is called once, when the first values are collected, after every check of the run
/// has passed (e.g. to check that the destination is no loaded plugin). With
/// RunOptions::check_only nothing runs and the result is empty. Throws as RunToText and
/// CollectResultArrays do, messages naming "the output of PIPELINE".
ResultArrays RunToArrays(const Pipeline& p, const RunOptions& options,
                         const std::function<void()>& started = {});
ResultArrays RunToArrays(const Pipeline& p, const Registry& reg, const RunOptions& options,
                         const std::function<void()>& started = {});

}  // namespace imuconv::pipeline
