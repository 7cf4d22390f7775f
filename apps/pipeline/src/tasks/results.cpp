#include "results.h"

#include <cstdio>

#include "../spec/pipeline_spec.h"
#include "imuconv/pipeline/errors.h"
#include "imuconv/printable.h"
#include "task.h"

namespace imuconv::pipeline {
namespace {

std::string Bytes(double b) {
  char buf[32];
  if (b >= 1024.0 * 1024 * 1024)
    std::snprintf(buf, sizeof buf, "%.1f GiB", b / (1024.0 * 1024 * 1024));
  else if (b >= 1024.0 * 1024)
    std::snprintf(buf, sizeof buf, "%.1f MiB", b / (1024.0 * 1024));
  else if (b >= 1024.0)
    std::snprintf(buf, sizeof buf, "%.1f KiB", b / 1024.0);
  else
    std::snprintf(buf, sizeof buf, "%.0f bytes", b);
  return buf;
}

std::size_t StringBytes(const std::string& s) { return s.capacity() > 15 ? s.capacity() + 1 : 0; }

}  // namespace

std::size_t KeptBytes(const MeasRecord& r) {
  return sizeof(MeasRecord) + StringBytes(r.pointer) + StringBytes(r.convention) +
         StringBytes(r.jacobian_convention);
}
std::size_t KeptBytes(const PropRecord& r) {
  return sizeof(PropRecord) + StringBytes(r.convention);
}

std::unordered_map<std::string, std::string> ReferencedTasks(const PipelineSpec& s) {
  std::unordered_map<std::string, std::string> refs;
  for (const auto& t : s.tasks)
    t->references(
        [&](const std::string& name, const std::string& pointer) { refs.emplace(name, pointer); });
  return refs;
}

std::size_t CheckKeptMemory(const PipelineSpec& s,
                            const std::unordered_map<std::string, std::string>& referenced,
                            const std::function<std::size_t(const std::string& file)>& file_count,
                            std::size_t limit) {
  // Records per task, in task order (a task can only name an earlier one).
  std::unordered_map<std::string, std::size_t> count;
  const auto measurements = [&](const MeasurementsSpec& m) -> std::size_t {
    if (!m.task.empty()) {
      const auto it = count.find(m.task);
      return it == count.end() ? 0 : it->second;
    }
    return m.file.empty() ? 0 : file_count(m.file);
  };
  double total = 0;  // double: a product of two large counts must not wrap
  for (const auto& t : s.tasks) {
    const KeptRecords kept = t->kept_records(measurements);
    const std::size_t n = kept.count, each = kept.bytes_each;
    const char* what = kept.what;
    count[t->name] = n;
    const auto ref = referenced.find(t->name);
    if (ref == referenced.end() || n == 0) continue;
    const double bytes = static_cast<double>(n) * static_cast<double>(each);
    if (total + bytes > static_cast<double>(limit))
      throw ConfigError(
          s.file,
          {{t->pointer,
            "task " + Quoted(t->name) + " has " + std::to_string(n) + " " + what +
                "(s), and a later task uses them (" + Printable(ref->second) +
                "), so they are kept in memory: " + std::to_string(n) + " x " +
                std::to_string(each) + " bytes = " + Bytes(bytes) +
                (total > 0 ? " (plus " + Bytes(total) + " kept for earlier tasks)"
                           : std::string()) +
                ", over the limit of " + Bytes(static_cast<double>(limit)) +
                " (RunOptions::max_kept_bytes). Use fewer intervals, or do not name this task "
                "from a later one: results no task names are written and dropped, not kept"}});
    total += bytes;
  }
  return static_cast<std::size_t>(total);
}

}  // namespace imuconv::pipeline
