// The imuconv benchmark set (Google Benchmark). Every benchmark reports items_per_second in
// IMU samples per second over a 10 s interval at 200 Hz (2001 samples, 2000 steps).
#pragma once

namespace imuconv::bench {

/// Registers the set: BM_Preintegrate/{manifold,tangent}, BM_Propagate/{euler,midpoint,rk4},
/// BM_PreintegrateByPropagation/rk4, BM_Conversion/left/gtsam_navstate, BM_PluginOverhead/rk4;
/// and BM_PreintegrateInstance/{manifold,tangent}/{baseline,avx2,avx512} for each compiled
/// instance of the native kernels this CPU can run.
void RegisterAll();

/// Initialises Google Benchmark with argv, registers the set and runs it; returns an exit code.
int Main(int argc, char** argv);

}  // namespace imuconv::bench
