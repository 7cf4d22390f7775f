// `midpoint_substeps`: a user's integrator built on imuconv's public kernels. Each sample
// interval is split into 4 substeps with the input interpolated linearly between the samples,
// and every substep holds the mean of its two ends (the midpoint rule), so the input at the
// middle of each substep is used. It is imuconv's `midpoint` on a 4x denser window: the same
// exact transition matrix and discrete noise (sigma^2/dt per substep), native chart `left`.
// The kernel freezes the rotation over a step for p and v, which is first order in the step:
// four substeps cut `midpoint`'s difference from `rk4` by four (check_conventions.cpp).
#include <imuconv/kernels/euler.h>
#include <imuconv/plugin/kernel_plugin.h>
#include <imuconv/plugin_abi.h>

#include <vector>

namespace {

constexpr int kSubsteps = 4;

struct MidpointSubsteps {
  imuconv::Status operator()(const imuconv::PropagationInput& in,
                             imuconv::PropagationResult& out) const {
    const imuconv::SampleWindow& w = in.window;
    std::vector<imuconv::ImuSample> dense;
    dense.reserve((w.size() - 1) * kSubsteps + 1);
    for (std::size_t k = 0; k + 1 < w.size(); ++k)
      for (int j = 0; j < kSubsteps; ++j)
        dense.push_back(imuconv::InterpolateSample(
            w[k], w[k + 1], w[k].t + (w[k + 1].t - w[k].t) * j / double(kSubsteps)));
    dense.push_back(w[w.size() - 1]);
    imuconv::PropagationInput fine = in;
    fine.window.samples = dense.data();
    fine.window.begin = 1;
    fine.window.end = dense.size() - 1;
    fine.window.first = dense.front();
    fine.window.last = dense.back();
    return imuconv::kernels::PropagateHeld<imuconv::kernels::Hold::Midpoint>(fine, out);
  }
};

}  // namespace

IMUCONV_PLUGIN(Propagator, imuconv::plugin::KernelPropagator<MidpointSubsteps>, "midpoint_substeps",
               "1.0.0",
               "midpoint rule on 4 linearly interpolated substeps per sample interval; native left")
