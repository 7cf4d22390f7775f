// `basalt`: Basalt's preintegration (IntegratedImuMeasurement) fed as Basalt's VIO feeds it:
// each sample held over the step that ends at its timestamp (the interval's first knot
// unused). Per-sample variances sigma^2/dt at each step's own dt, which are Basalt's
// sigma^2 f on regularly sampled data (kernels/basalt.h). Covariance and bias Jacobian in
// the `basalt` increment convention; the bias blocks are the random walks over the interval.
#include "imuconv/kernels/basalt.h"

#include "imuconv/plugin/kernel_plugin.h"
#include "imuconv/plugin_abi.h"

namespace {
using Scheme = imuconv::kernels::BasaltScheme<imuconv::kernels::BasaltFeeding::kNative>;
}  // namespace

IMUCONV_PLUGIN(
    Preintegrator, imuconv::plugin::KernelPreintegrator<Scheme>, "basalt", "1.0.0",
    "Basalt IntegratedImuMeasurement, each sample held over the step ending at its stamp")
