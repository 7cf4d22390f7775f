// Pipeline: a loaded, validated pipeline document (pipeline.h).
#include <filesystem>
#include <unordered_set>

#include "../tasks/task.h"
#include "imuconv/pipeline/input_registry.h"
#include "imuconv/pipeline/json_parse.h"
#include "imuconv/pipeline/pipeline.h"
#include "parse.h"

namespace imuconv::pipeline {

namespace fs = std::filesystem;

Pipeline::Pipeline(std::unique_ptr<PipelineSpec> s) : spec_(std::move(s)) {}
Pipeline::Pipeline(Pipeline&&) noexcept = default;
Pipeline& Pipeline::operator=(Pipeline&&) noexcept = default;
Pipeline::~Pipeline() = default;

Pipeline Pipeline::Load(const std::string& path) {
  const json doc = ParseJsonFile(path);
  RegisterInputPath(path, "the pipeline");  // named as such when an output would replace it
  const std::string base = fs::path(path).parent_path().string();
  return FromJson(doc, path, base.empty() ? "." : base);
}

Pipeline Pipeline::FromJson(const json& doc, const std::string& file, const std::string& base_dir) {
  return Pipeline(ParseSpec(doc, file, base_dir));
}

const std::string& Pipeline::file() const { return spec_->file; }
const std::vector<std::string>& Pipeline::plugin_dirs() const { return spec_->plugin_dirs; }
const std::optional<std::string>& Pipeline::output_path() const { return spec_->output; }

std::vector<std::string> Pipeline::step_tasks() const {
  std::vector<std::string> names;
  for (const auto& t : spec_->tasks)
    if (t->type == "propagate_by_preintegration") names.push_back(t->name);
  return names;
}

bool Pipeline::has_ground_truth() const { return spec_->gt.has_value(); }

std::vector<std::string> Pipeline::input_files() const {
  std::vector<std::string> files;
  std::unordered_set<std::string> seen;  // linear in the number of tasks
  const auto add = [&](const std::string& f) {
    if (!f.empty() && seen.insert(f).second) files.push_back(f);
  };
  add(spec_->file);
  add(spec_->noise_file);
  if (spec_->imu && spec_->imu->format != ImuSourceSpec::Format::Inline) add(spec_->imu->path);
  if (spec_->gt) add(spec_->gt->path);
  for (const auto& t : spec_->tasks) {
    if (const MeasurementsSpec* m = t->measurements()) add(m->file);
    if (const std::string* f = t->input_file()) add(*f);
  }
  return files;
}

}  // namespace imuconv::pipeline
