// imuconv convert --what W --from A --to B (--state S.json | --increment D.json) [--matrix M.json]
//                 [--state-end E.json] [--json]
// One conversion between two conventions at a value, with no pipeline file: what a pipeline's
// "convert" task does, for the commonest question ("my OpenVINS covariance in GTSAM's chart").
//   covariance            J S J^T, J = d dx_B / d dx_A at the state          (state conventions)
//   transition            J_e Phi J_s^{-1} from the state to --state-end     (state conventions)
//   jacobian              J itself                                           (state conventions)
//   increment_covariance  J S J^T at the increment                          (increment conventions)
//   increment_jacobian    J itself at the increment                         (increment conventions)
// The matrix file takes any form a pipeline's "matrix" takes; when it declares its
// "convention", that must be A (and A may then be left out), and its "blocks" must be A's.
#include <Eigen/Geometry>
#include <iostream>
#include <memory>
#include <optional>

#include "imuconv/cli/commands.h"
#include "imuconv/cli/exit_codes.h"
#include "imuconv/cli/non_finite_result.h"
#include "imuconv/pipeline/json_io.h"
#include "imuconv/printable.h"

namespace imuconv::cli {
namespace {

enum class What { Covariance, Transition, Jacobian, IncrementCovariance, IncrementJacobian };

struct ConvertOptions {
  std::string what, from, to, state, state_end, increment, matrix;
  bool as_json = false;
};

struct Request {
  What what{};
  PluginKind kind{};
  bool covariance = false, jacobian = false;
};

Request Classify(const std::string& what) {
  Request r;
  r.what = what == "covariance"             ? What::Covariance
           : what == "transition"           ? What::Transition
           : what == "jacobian"             ? What::Jacobian
           : what == "increment_covariance" ? What::IncrementCovariance
                                            : What::IncrementJacobian;
  const bool increment = r.what == What::IncrementCovariance || r.what == What::IncrementJacobian;
  r.kind = increment ? PluginKind::IncrementConvention : PluginKind::StateConvention;
  r.covariance = r.what == What::Covariance || r.what == What::IncrementCovariance;
  r.jacobian = r.what == What::Jacobian || r.what == What::IncrementJacobian;
  return r;
}

void CheckOptions(const ConvertOptions& o, const Request& q) {
  const bool increment = q.kind == PluginKind::IncrementConvention;
  if (increment && o.increment.empty()) throw UsageError{"--what " + o.what + " needs --increment"};
  if (!increment && o.state.empty()) throw UsageError{"--what " + o.what + " needs --state"};
  if (increment && !o.state.empty())
    throw UsageError{"--what " + o.what +
                     " converts at an increment: give --increment, not --state"};
  if (!increment && !o.increment.empty())
    throw UsageError{"--what " + o.what + " converts at a state: give --state, not --increment"};
  if ((q.what == What::Transition) != !o.state_end.empty())
    throw UsageError{q.what == What::Transition
                         ? "--what transition needs --state-end (the transition's end state)"
                         : "--state-end is only for --what transition"};
  if (q.jacobian && !o.matrix.empty())
    throw UsageError{"--what " + o.what + " computes a matrix; it takes no --matrix"};
  if (!q.jacobian && o.matrix.empty()) throw UsageError{"--what " + o.what + " needs --matrix"};
}

int ExecuteConvert(const CommandContext& ctx, const ConvertOptions& o) {
  const Request q = Classify(o.what);
  CheckOptions(o, q);
  // Every file is read and checked before the plugins are loaded: a bad file is the first
  // thing to report and needs no plugin.
  std::optional<pipeline::Matrix15In> M;
  if (!o.matrix.empty()) M = pipeline::ReadMatrixFile(o.matrix, q.covariance);
  ImuState x_s, x_e;
  PreintIncrement d;
  if (!o.state.empty()) x_s = pipeline::ReadStateFile(o.state);
  if (!o.state_end.empty()) x_e = pipeline::ReadStateFile(o.state_end);
  if (!o.increment.empty()) d = pipeline::ReadIncrementFile(o.increment);

  std::string from = o.from;
  if (from.empty() && !(M && M->convention))
    throw UsageError{"--from is required (or a --matrix file that declares its \"convention\")"};
  if (M && M->convention) {
    if (from.empty()) from = *M->convention;
    if (*M->convention != from) {
      PrintError(o.matrix + ": /convention: the matrix declares '" + Printable(*M->convention) +
                 "' but --from is '" + Printable(from) + "'");
      return kExitBadInput;
    }
  }
  Registry reg;
  const auto issues = LoadRegistry(reg, ctx);
  for (const auto& id : {from, o.to}) {
    const std::string unknown = UnknownConventionMessage(reg, q.kind, id, issues);
    if (unknown.empty()) continue;
    PrintError(unknown);
    return kExitBadInput;
  }
  const auto bf = pipeline::Blocks(reg, q.kind, from);
  const auto bt = pipeline::Blocks(reg, q.kind, o.to);
  if (M && M->blocks && *M->blocks != bf) {
    PrintError(o.matrix + ": /blocks: the matrix declares the block order " +
               Printable(nlohmann::json(*M->blocks).dump()) + " but '" + from +
               "' orders its blocks " + nlohmann::json(bf).dump());
    return kExitBadInput;
  }

  Mat15 result;
  switch (q.what) {
    case What::Covariance:
      result = reg.convert_covariance(from, o.to, x_s, M->m);
      break;
    case What::Transition:
      result = reg.convert_transition(from, o.to, x_s, x_e, M->m);
      break;
    case What::Jacobian:
      result = reg.conversion(from, o.to, x_s);
      break;
    case What::IncrementJacobian:
      result = reg.conversion(from, o.to, d);
      break;
    case What::IncrementCovariance:
      result = reg.convert_covariance(from, o.to, d, M->m);
      break;
  }
  const std::string non_finite = NonFiniteResultMessage(
      result, "convert", o.what, from, o.to,
      std::string(o.state.empty() ? "increment" : "state") + (M ? " or matrix" : ""));
  if (!non_finite.empty()) {
    PrintError(non_finite);
    return kExitBadInput;
  }

  if (o.as_json) {
    using nlohmann::json;
    const auto chart = [](const Mat15& m, const std::string& conv,
                          const std::vector<std::string>& blocks) {
      return json{{"convention", conv}, {"blocks", blocks}, {"matrix", pipeline::MatrixToJson(m)}};
    };
    json j = {{"what", o.what}, {"from", from}, {"to", o.to}};
    if (q.kind == PluginKind::StateConvention) {
      j["state"] = pipeline::StateToJson(x_s);
      if (q.what == What::Transition) j["state_end"] = pipeline::StateToJson(x_e);
    } else {
      const Eigen::Quaterniond q(d.dR);
      j["increment"] = {{"q_wxyz", {q.w(), q.x(), q.y(), q.z()}},
                        {"dp", pipeline::Vec3ToJson(d.dp)},
                        {"dv", pipeline::Vec3ToJson(d.dv)},
                        {"dbg", pipeline::Vec3ToJson(d.dbg)},
                        {"dba", pipeline::Vec3ToJson(d.dba)}};
    }
    if (M) j["input"] = chart(M->m, from, bf);
    j["result"] = q.jacobian ? pipeline::MixedMatrixToJson(result, o.to, bt, from, bf)
                             : chart(result, o.to, bt);
    std::cout << pipeline::PrettyJson(j) << "\n";
    return 0;
  }
  if (q.jacobian)
    std::cout << "d dx[" << o.to << "] / d dx[" << from << "]\nrows: " << o.to
              << " blocks, columns: " << from << " blocks\n\n";
  else
    std::cout << o.what << " in " << o.to << " (converted from " << from
              << ")\nrows and columns: " << o.to << " blocks\n\n";
  PrintLabelledMatrix(std::cout, result, bt, q.jacobian ? bf : bt);
  return 0;
}

// The command line of imuconv convert: its description, and its flags onto the options.
void DeclareConvertCommand(CLI::App* sub, ConvertOptions* o) {
  sub->description(
      "Convert a covariance, a transition matrix or a conversion "
      "Jacobian between two conventions at a state "
      "or an increment (no pipeline file)");
  sub->add_option("--what", o->what, "What to convert")
      ->required()
      ->check(CLI::IsMember(
          {"covariance", "transition", "jacobian", "increment_covariance", "increment_jacobian"}));
  sub->add_option("--from", o->from,
                  "Convention the matrix is in (may be left out when the matrix file declares it)")
      ->type_name("A");
  sub->add_option("--to", o->to, "Convention to express it in")->required()->type_name("B");
  sub->add_option(
         "--state", o->state,
         "State file {\"p\", \"q_wxyz\", \"v\", \"bg\", \"ba\"}: the estimate the chart is at")
      ->type_name("S.json");
  sub->add_option("--state-end", o->state_end, "End state of a transition matrix")
      ->type_name("E.json");
  sub->add_option("--increment", o->increment,
                  "Increment file {\"q_wxyz\" or \"R\", \"dp\", \"dv\", \"dbg\", \"dba\"}")
      ->type_name("D.json");
  sub->add_option("--matrix", o->matrix,
                  "15x15 matrix file: an array of rows, {\"diagonal\"}, {\"sigma\"} or "
                  "{\"convention\", \"blocks\", \"matrix\"}")
      ->type_name("M.json");
  sub->add_flag("--json", o->as_json,
                "Print JSON: the input and the result, each with its convention and blocks");
}

}  // namespace

void RegisterConvertCommand(CLI::App& app, CommandContext& ctx) {
  AddCommand(app, ctx, "convert", DeclareConvertCommand, ExecuteConvert);
}

}  // namespace imuconv::cli
