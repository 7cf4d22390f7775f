// The task kinds: "type" -> its parser. A new kind is one file in this directory (defining
// its parser) and one line in this list.
#include "task.h"

// KIND(type, parser), in the schema's order.
#define IMUCONV_TASK_KINDS(KIND)                                      \
  KIND("propagate", ParsePropagate)                                   \
  KIND("preintegrate", ParsePreintegrate)                             \
  KIND("propagate_by_preintegration", ParsePropagateByPreintegration) \
  KIND("convert", ParseConvert)                                       \
  KIND("residual", ParseResidual)                                     \
  KIND("bias_update", ParseBiasUpdate)                                \
  KIND("check", ParseCheck)                                           \
  KIND("optimize", ParseOptimize)

namespace imuconv::pipeline {

#define IMUCONV_DECLARE_PARSER(type, parser) \
  std::unique_ptr<Task> parser(const ParseContext& ctx, const Node& n);
IMUCONV_TASK_KINDS(IMUCONV_DECLARE_PARSER)
#undef IMUCONV_DECLARE_PARSER

const std::vector<TaskKind>& TaskKinds() {
#define IMUCONV_KIND_ENTRY(type, parser) {type, parser},
  static const std::vector<TaskKind> kinds = {IMUCONV_TASK_KINDS(IMUCONV_KIND_ENTRY)};
#undef IMUCONV_KIND_ENTRY
  return kinds;
}

}  // namespace imuconv::pipeline
