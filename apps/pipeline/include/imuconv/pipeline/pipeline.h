// JSON pipelines: an IMU source, noise, gravity and an ordered list of named tasks
// (propagate, preintegrate, propagate_by_preintegration, convert, residual, bias_update).
// The format is described by schemas/pipeline.schema.json and docs in examples/README.md.
//
// Loading validates the structure by hand and reports every problem with its JSON pointer
// (unknown keys included); running then checks plugin ids against the registry and times
// against the data (again with pointers) before any task runs, and produces one output
// JSON document. Nothing is written here: the caller writes the document (atomically).
#pragma once

#include <functional>
#include <iosfwd>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "imuconv/pipeline/json_check.h"
#include "imuconv/registry.h"

namespace imuconv::pipeline {

struct PipelineSpec;  // the parsed document (apps/pipeline/src/spec.h)

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
  /// Every file the pipeline reads: the pipeline itself, the IMU and ground-truth files and
  /// the measurement files, each once, as resolved paths. An output must be none of them.
  std::vector<std::string> input_files() const;
  const PipelineSpec& spec() const { return *spec_; }

 private:
  explicit Pipeline(std::unique_ptr<PipelineSpec> s);
  std::unique_ptr<PipelineSpec> spec_;
};

struct RunOptions {
  /// Plugin directories searched before the pipeline's own plugin_dirs (e.g. --plugin-dir).
  std::vector<std::string> plugin_dirs;
  /// Plugin load problems are reported here as warnings (may be null).
  std::ostream* log = nullptr;
  /// The human-readable summary tables are printed here (may be null).
  std::ostream* summary = nullptr;
  /// Threads for independent intervals (the caller's included): 0 = every core
  /// (std::thread::hardware_concurrency()), 1 = serial. The output does not depend on it:
  /// it is the same, byte for byte, for any number of threads.
  unsigned threads = 0;
};

/// Receives the output document's text in order, in pieces.
using TextSink = std::function<void(std::string_view)>;

/// Runs and streams the output document (pretty-printed as PrettyJson lays it out; numbers in
/// the shortest form that reads back exactly) into `sink` while the tasks run, so that a large
/// document never has to be held in memory. The registry is loaded as by Run. On any error
/// the sink has received an incomplete document: write it to a temporary (AtomicFile) and
/// discard it on failure.
void RunToText(const Pipeline& p, const RunOptions& options, const TextSink& sink);
void RunToText(const Pipeline& p, const Registry& reg, const RunOptions& options, const TextSink& sink);

/// Loads the registry from RunOptions::plugin_dirs, the pipeline's plugin_dirs and the
/// default search path, then runs. Throws ConfigError / ReadError / Error naming the file.
/// The document is RunToText's text, parsed.
json Run(const Pipeline& p, const RunOptions& options);
/// Runs with a given registry (plugin_dirs of the pipeline and options are then ignored).
json Run(const Pipeline& p, const Registry& reg, const RunOptions& options);

}  // namespace imuconv::pipeline
