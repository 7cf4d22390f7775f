// The work of `imuconv plugins --check`'s child process (plugin_exercise.h): load one plugin
// file and call what it provides on a small test window.
#include "plugin_exercise.h"

#include <cmath>
#include <vector>

#include "imuconv/printable.h"
#include "imuconv/registry.h"
#include "imuconv/residual_cost_outputs.h"
#include "imuconv/residual_factor.h"
#include "imuconv/window.h"

namespace imuconv::cli {
namespace {

// 10 ms of a slowly turning, slightly accelerating IMU at 200 Hz: small enough to be instant
// for any integrator, not so special (all zero) that a broken one passes by luck.
std::vector<ImuSample> TestSamples() {
  std::vector<ImuSample> s(3);
  for (int k = 0; k < 3; ++k) {
    s[k].t = 0.005 * k;
    s[k].gyro = Vec3(0.01, -0.02, 0.03 + 0.001 * k);
    s[k].accel = Vec3(0.1, 0.2 - 0.01 * k, 9.81);
  }
  return s;
}

/// A sink that keeps nothing and checks what a residual plugin writes: balanced groups,
/// names, sizes and finite numbers (the pipeline's ResidualJsonSink checks the same as it
/// writes).
class CheckingSink final : public ResidualSink {
 public:
  void begin_group(const char* name) noexcept override {
    named(name);
    ++depth_;
  }
  void end_group() noexcept override {
    if (depth_ == 0) fail("closed a group it had not opened");
    if (depth_ > 0) --depth_;
  }
  void vector(const char* name, const double* v, int n) noexcept override { array(name, v, n, 1); }
  void matrix(const char* name, const double* m, int rows, int cols) noexcept override {
    array(name, m, rows, cols);
  }
  void mahalanobis_squared(double value) noexcept override {
    if (!std::isfinite(value) || value < 0.0)
      fail("gave a squared Mahalanobis distance < 0 or not finite");
  }
  std::string problem() const {
    return depth_ != 0 && problem_.empty() ? "left a group open" : problem_;
  }
  std::size_t values() const { return values_; }

 private:
  void fail(const char* what) noexcept {
    if (problem_.empty()) problem_ = what;
  }
  void named(const char* name) noexcept {
    if (name == nullptr || name[0] == '\0') fail("gave a null or empty name");
  }
  void array(const char* name, const double* data, int rows, int cols) noexcept {
    named(name);
    if (rows < 1 || cols < 1 || static_cast<long long>(rows) * cols > (1 << 20) || data == nullptr)
      return fail("gave an array of a size out of bounds or a null array");
    for (long long k = 0; k < static_cast<long long>(rows) * cols; ++k)
      if (!std::isfinite(data[k])) return fail("gave a value that is not finite");
    values_ += static_cast<std::size_t>(rows) * static_cast<std::size_t>(cols);
  }
  int depth_ = 0;
  std::size_t values_ = 0;
  std::string problem_;
};

ImuNoise TestNoise() {
  // gyro and accelerometer noise densities, then gyro and accelerometer random walks
  return ImuNoise{1.7e-4, 2e-3, 1.9e-5, 3e-3};
}

// A residual plugin's cost declaration (residual_cost_spec.h), which otherwise only building
// its Ceres factor reads: resolved against the built-in plugins (the file's own registry holds
// that file alone), then evaluate() run again through the sink that keeps what the declaration
// names, so that a declared output evaluate() never writes, or writes at another size, is found
// here and not in a user's optimization. A declaration in a state convention that is not built
// in (the user's own) cannot be checked here; that is said, not passed over.
std::string CheckCostDeclaration(const ResidualFactor& factor, const std::string& who,
                                 const Preintegrated& m, const ImuState& x_s, const ImuState& x_e,
                                 const Vec3& gravity) {
  const ResidualCostSpec* spec = factor.cost_spec();
  if (spec == nullptr) return "it declares no Ceres cost (cost_spec() is null)";
  Registry builtins;
  if (Registry::has_compiled_in())
    builtins.load_compiled_in();
  else
    (void)builtins.load_directory(Registry::default_plugin_dir());  // a failure shows below
  std::string chart;  // a broken name is ResolveResidualCost's to report
  if (ReadCostName(spec->state_convention, chart) &&
      !builtins.has(PluginKind::StateConvention, chart))
    return "its cost declaration is in state convention " + Quoted(chart) +
           ", which is not built in: it is checked where a factor is built with a registry "
           "that has it";
  ResidualCostOutputs outputs;
  try {
    outputs = ResolveResidualCost(builtins, factor);
  } catch (const Error& e) {
    throw Error(who + ": its cost declaration is broken: " + e.what());
  }
  ResidualOutputValues values;
  const std::string problem = EvaluateResidualCost(factor, outputs, m, x_s, x_e, gravity, values);
  if (!problem.empty())
    throw Error(who +
                ": evaluate() on a 10 ms test measurement does not write what its cost "
                "declaration names: " +
                problem);
  return "its cost declaration (" + std::to_string(outputs.n) + " rows, Jacobians in " +
         Quoted(chart) + ") matches what evaluate() writes";
}

}  // namespace

std::string ExercisePlugin(const std::string& file) {
  Registry reg;
  reg.load_file(file);
  const PluginInfo& p = reg.plugins().back();
  std::string what =
      std::string(KindName(p.kind)) + " " + Quoted(p.id) + " " + Printable(p.version);
  const std::string who =
      std::string(KindName(p.kind)) + " " + Quoted(p.id) + " in " + Quoted(file);
  const auto samples = TestSamples();
  SampleWindow w;
  if (const Status st = MakeWindow(samples.data(), samples.size(), 0.0, 0.01, w); !st.ok())
    throw Error("internal: the test window cannot be built: " + st.message());
  if (p.kind == PluginKind::Propagator) {
    PropagationInput in;
    in.window = w;
    in.noise = TestNoise();
    in.cov_s = Mat15::Identity() * 1e-6;
    in.x_s.v = Vec3(0.5, 0.0, 0.0);
    PropagationResult out;
    const Status st = reg.propagator(p.id)->propagate(in, out);
    if (!st.ok())
      throw Error(who + ": propagate() failed on a 10 ms test window: " + Printable(st.message()));
    if (!out.x_e.R.allFinite() || !out.x_e.p.allFinite() || !out.x_e.v.allFinite() ||
        !out.x_e.bg.allFinite() || !out.x_e.ba.allFinite() || !out.Phi.allFinite() ||
        !out.cov.allFinite())
      throw Error(who + ": propagate() returned non-finite values on a 10 ms test window");
    what += "; propagate() ran on a 10 ms test window";
  } else if (p.kind == PluginKind::Preintegrator) {
    PreintegrationInput in;
    in.window = w;
    in.noise = TestNoise();
    Preintegrated out;
    const Status st = reg.preintegrator(p.id)->integrate(in, out);
    if (!st.ok())
      throw Error(who + ": integrate() failed on a 10 ms test window: " + Printable(st.message()));
    if (!AllFinite(out))
      throw Error(who + ": integrate() returned non-finite values on a 10 ms test window");
    what += "; integrate() ran on a 10 ms test window";
  } else if (p.kind == PluginKind::Residual) {
    // A 10 ms measurement in any chart: the identity increment with a small diagonal
    // covariance and no bias sensitivity, between two states it nearly predicts.
    Preintegrated m;
    m.dt = 0.01;
    m.cov = Mat15::Identity() * 1e-6;
    m.convention = p.native_convention;
    m.jacobian_convention = p.native_convention;
    ImuState xs, xe;
    xs.v = Vec3(0.5, 0.0, 0.0);
    xe.p = Vec3(0.005, 0.0, 0.0);
    xe.v = xs.v;
    const Vec3 gravity(0.0, 0.0, -9.81);
    const std::shared_ptr<const ResidualFactor> factor = reg.residual_factor(p.id);
    CheckingSink sink;
    const Status st = factor->evaluate(m, xs, xe, gravity, sink);
    if (!st.ok())
      throw Error(who +
                  ": evaluate() failed on a 10 ms test measurement: " + Printable(st.message()));
    if (!sink.problem().empty())
      throw Error(who + ": evaluate() on a 10 ms test measurement " + sink.problem());
    if (sink.values() == 0)
      throw Error(who + ": evaluate() wrote nothing on a 10 ms test measurement");
    what += "; evaluate() ran on a 10 ms test measurement (" + std::to_string(sink.values()) +
            " values); " + CheckCostDeclaration(*factor, who, m, xs, xe, gravity);
  } else {
    what += "; charts and Jacobians checked";
  }
  return what;
}

}  // namespace imuconv::cli
