// The work of `imuconv plugins --check`'s child process (plugin_exercise.h): load one plugin
// file and call what it provides on a small test window.
#include "plugin_exercise.h"

#include <cmath>
#include <vector>

#include "imuconv/printable.h"
#include "imuconv/registry.h"
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

ImuNoise TestNoise() {
  // gyro and accelerometer noise densities, then gyro and accelerometer random walks
  return ImuNoise{1.7e-4, 2e-3, 1.9e-5, 3e-3};
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
    if (!std::isfinite(out.dt) || !out.delta.dR.allFinite() || !out.delta.dp.allFinite() ||
        !out.delta.dv.allFinite() || !out.cov.allFinite() || !out.J_bias.allFinite())
      throw Error(who + ": integrate() returned non-finite values on a 10 ms test window");
    what += "; integrate() ran on a 10 ms test window";
  } else {
    what += "; charts and Jacobians checked";
  }
  return what;
}

}  // namespace imuconv::cli
