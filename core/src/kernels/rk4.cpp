// The entry points of the rk4 kernel (kernels/rk4.h): the input checks, the instance the CPU
// runs (dispatch.cpp), and the kernel compiled for the default target. That compilation is the
// portable one (any compiler, any CPU: Isa::kPortable) and, with GCC or Clang, also the
// baseline instance's (instance_baseline.cpp): the step is plain loops over arrays, with no
// vector-extension form to compile at the baseline's width, so a second default-target copy
// would be the same machine code.
#include "imuconv/kernels/rk4.h"

#include "instances.h"
#include "rk4_window.h"

namespace imuconv::kernels {

namespace detail {

void Rk4DefaultTarget(const PropagationInput& in, Outputs outputs, int substeps,
                      PropagationResult& out) {
  Rk4Window(in, outputs, substeps, out);
}

}  // namespace detail

void IntegrateRk4Window(const PropagationInput& in, PropagationResult& out, Outputs outputs,
                        int substeps, Isa isa) {
  const detail::Instance* simd = detail::SimdInstance(detail::ResolveIsa(isa));
  if (simd)
    simd->rk4(in, outputs, substeps, out);
  else
    detail::Rk4DefaultTarget(in, outputs, substeps, out);
}

Status PropagateRk4(const PropagationInput& in, PropagationResult& out, int substeps, Isa isa) {
  if (substeps < 1) return Status::Error("rk4: substeps must be at least 1");
  if (!IsaAvailable(isa))
    return Status::Error("rk4: the requested instruction set is not available on this CPU");
  Status st = CheckPropagationInput(in);
  if (st.ok()) IntegrateRk4Window(in, out, Outputs::All, substeps, isa);
  return st;
}

}  // namespace imuconv::kernels
