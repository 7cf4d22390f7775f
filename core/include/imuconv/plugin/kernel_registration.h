// The one-line registration of a propagator or preintegrator plugin whose numerics are a kernel
// of the core named in place (plugin/kernel_plugin.h): the kernel type is written in the
// registration line itself, last, so that a template instance with several arguments (a
// scheme and its noise reading, say) needs no alias of its own first:
//
//   IMUCONV_KERNEL_PROPAGATOR("fast_lio2", "1.0.0", "one line summary",
//                             imuconv::kernels::FastLio2Propagator<Transition, Reading>)
//
// This is IMUCONV_PLUGIN (plugin_abi.h) with the kind and the KernelPropagator or
// KernelPreintegrator wrapper filled in, and nothing else: the ABI handshake, the objects
// created and destroyed inside the shared object and the exceptions contained at the boundary
// are IMUCONV_PLUGIN's and the wrapper's, unchanged. Use once per plugin source file, at global
// scope. A kernel struct declared in the plugin file itself may as well be named in an
// IMUCONV_PLUGIN line directly.
#pragma once

#include "imuconv/plugin/kernel_plugin.h"
#include "imuconv/plugin_abi.h"

// The wrapped kernel as one name (IMUCONV_PLUGIN's IMPL cannot hold a template's comma);
// internal to the two macros below.
#define IMUCONV_KERNEL_PLUGIN_(KIND, WRAPPER, ID, VERSION, SUMMARY, ...) \
  namespace {                                                            \
  using ImuconvKernelPlugin = ::imuconv::plugin::WRAPPER<__VA_ARGS__>;   \
  }                                                                      \
  IMUCONV_PLUGIN(KIND, ImuconvKernelPlugin, ID, VERSION, SUMMARY)

/// A propagator plugin whose propagate() is the kernel's (KernelPropagator<kernel>).
#define IMUCONV_KERNEL_PROPAGATOR(ID, VERSION, SUMMARY, ...) \
  IMUCONV_KERNEL_PLUGIN_(Propagator, KernelPropagator, ID, VERSION, SUMMARY, __VA_ARGS__)

/// A preintegrator plugin whose integrate() is the kernel's (KernelPreintegrator<kernel>).
#define IMUCONV_KERNEL_PREINTEGRATOR(ID, VERSION, SUMMARY, ...) \
  IMUCONV_KERNEL_PLUGIN_(Preintegrator, KernelPreintegrator, ID, VERSION, SUMMARY, __VA_ARGS__)
