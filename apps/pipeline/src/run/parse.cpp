// The pipeline document's top-level keys; each task's "type" picks its parser from the list
// of task kinds (tasks/kinds.cpp).
#include <algorithm>
#include <filesystem>

#include "../spec/sources.h"
#include "../tasks/task.h"
#include "imuconv/pipeline/pipeline.h"
#include "imuconv/printable.h"
#include "parse.h"

namespace imuconv::pipeline {
namespace {

namespace fs = std::filesystem;

bool ValidName(const std::string& s) {
  return !s.empty() && std::all_of(s.begin(), s.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
           c == '-' || c == '.';
  });
}

/// A task: its header (type, name, description), then its kind's keys. Nothing for a task
/// that is not an object or whose type is unknown (the type decides the keys, so only the
/// type error is reported).
std::unique_ptr<const Task> ReadTask(ParseContext& ctx, const Node& n) {
  static const std::vector<std::string> kTypes = [] {
    std::vector<std::string> types;
    for (const auto& k : TaskKinds()) types.push_back(k.type);
    return types;
  }();
  if (!n.is_object()) {
    n.fail("expected a task object, found " + TypeName(n.value()));
    return nullptr;
  }
  const auto type_node = n.get("type", true);
  std::optional<std::string> type;
  if (type_node) type = type_node->one_of(kTypes, "task types");
  const auto name = n.string("name", true);
  if (name) {
    if (!ValidName(*name))
      n.checker().error(
          n.child_pointer("name"),
          "expected a name of letters, digits, '_', '-' and '.', found " + QuotedShort(*name));
    else if (ctx.earlier(*name))
      n.checker().error(n.child_pointer("name"), "duplicate task name " + Quoted(*name));
  }
  const auto description = n.string("description", false);
  if (!type) {
    if (name) ctx.remember(*name, "?");
    return nullptr;
  }
  const auto kind = std::find_if(TaskKinds().begin(), TaskKinds().end(),
                                 [&](const TaskKind& k) { return *type == k.type; });
  std::unique_ptr<Task> t = kind->parse(ctx, n);
  t->type = *type;
  t->pointer = n.pointer();
  if (name) t->name = *name;
  if (description) t->description = *description;
  if (name) ctx.remember(*name, *type);
  return t;
}

}  // namespace

std::unique_ptr<PipelineSpec> ParseSpec(const json& doc, const std::string& file,
                                        const std::string& base_dir) {
  auto spec = std::make_unique<PipelineSpec>();
  spec->file = file;
  spec->base_dir = base_dir;
  Checker c(file);
  const Node root(doc, "", c);
  if (!root.expect_object({"$schema", "description", "plugin_dirs", "allow_plugin_override",
                           "gravity", "noise", "imu", "ground_truth", "output", "omit", "tasks",
                           "allow_empty_intervals"}))
    c.throw_if_errors();
  ParseContext ctx(c, base_dir);
  if (auto d = root.string("description", false)) spec->description = *d;
  root.string("$schema", false);
  if (auto pn = root.get("plugin_dirs", false))
    if (auto l = pn->string_list(true))
      for (const auto& d : *l) spec->plugin_dirs.push_back(ctx.resolve(d));
  if (auto b = root.boolean("allow_plugin_override", false)) spec->allow_plugin_override = *b;
  if (auto b = root.boolean("allow_empty_intervals", false)) spec->allow_empty_intervals = *b;
  // A pipeline (perhaps someone else's) may only write inside its own directory; -o, typed by
  // the user, is not restricted. Lexical check: a symbolic link inside the directory is trusted.
  if (auto o = root.string("output", false)) {
    const fs::path rel = fs::path(*o).lexically_normal();
    if (o->empty() || o->find('\0') != std::string::npos || rel.is_absolute() ||
        rel.has_root_name() || rel.has_root_directory() || (!rel.empty() && *rel.begin() == ".."))
      c.error("/output",
              "expected a relative path inside the pipeline's directory (not absolute, not leading "
              "out of it with "
              "'..'); to write anywhere else, give the output on the command line with -o");
    else
      spec->output = ctx.resolve(*o);
  }
  if (auto on = root.get("omit", false)) {
    if (!on->is_array()) {
      on->fail("expected an array of names (Phi, cov, J_bias, R, reference), found " +
               TypeName(on->value()));
    } else {
      std::vector<std::string> seen;
      for (std::size_t i = 0; i < on->size(); ++i) {
        const auto what = (*on)[i].one_of({"Phi", "cov", "J_bias", "R", "reference"});
        if (!what) continue;
        if (std::find(seen.begin(), seen.end(), *what) != seen.end())
          (*on)[i].fail("'" + *what + "' is listed twice");
        seen.push_back(*what);
        OmitSpec& o = spec->omit;
        if (*what == "Phi") o.Phi = true;
        if (*what == "cov") o.cov = true;
        if (*what == "J_bias") o.J_bias = true;
        if (*what == "R") o.R = true;
        if (*what == "reference") o.reference = true;
      }
    }
  }
  if (auto g = root.vec3("gravity", false)) spec->gravity = *g;
  if (auto nn = root.get("noise", false)) {
    spec->has_noise = true;
    if (auto q = NoiseFormFromJson(*nn, base_dir, &spec->noise_file)) spec->noise = *q;
  }
  if (auto in = root.get("imu", false)) {
    ctx.has_imu = true;
    spec->imu = ReadImuSource(ctx, *in);
  }
  if (auto gn = root.get("ground_truth", false)) {
    ctx.has_gt = true;
    spec->gt = ReadGroundTruthSource(ctx, *gn);
    if (!root.has("imu"))
      c.error(gn->pointer(),
              "ground truth is put on the IMU data's time axis: add a top-level /imu source");
  }
  if (auto tn = root.get("tasks", true)) {
    if (!tn->is_array() || tn->size() == 0) {
      tn->fail("expected a non-empty array of tasks, found " +
               (tn->is_array() ? std::string("an empty array") : TypeName(tn->value())));
    } else {
      spec->tasks.reserve(tn->size());
      for (std::size_t i = 0; i < tn->size(); ++i)
        if (auto t = ReadTask(ctx, (*tn)[i])) spec->tasks.push_back(std::move(t));
    }
  }
  // The noise is required by the tasks that integrate IMU samples, and only by them (a
  // pipeline of conversions, or of residuals of measurement files, has none to give).
  if (!spec->has_noise)
    for (const auto& t : spec->tasks)
      if (t->intervals()) {
        c.error("/noise", "required key is missing: task '" + Printable(t->name) + "' (" +
                              t->pointer + ", " + t->type + ") integrates IMU samples with it");
        break;
      }
  c.throw_if_errors();
  return spec;
}

}  // namespace imuconv::pipeline
