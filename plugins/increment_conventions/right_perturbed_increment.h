// The one-line registration of an increment convention that is RightPerturbedIncrementChart
// (imuconv/plugin/convention.h): additive dp, dv, Delta R = Delta R^ Exp(dtheta), the bias
// entry Delta b = Delta b^ + BIAS_SIGN db, in the block order B0..B4 (Block names, bare). Its
// Jacobians to and from `preint_reference` are the permutation with that sign, both ways, so
// the order and the sign are all such a plugin states besides its IMUCONV_PLUGIN facts:
//
//   IMUCONV_RIGHT_PERTURBED_INCREMENT("my_system", "1.0.0", "one line summary",
//                                     +1, theta, p, v, bg, ba)
//
// This is IMUCONV_PLUGIN (plugin_abi.h) with the order and the chart declared first, and
// nothing else. Use once per plugin source file, at global scope. Shared by the increment
// conventions of this folder (one source file is one plugin: this header is not one).
#pragma once

#include "imuconv/plugin/convention.h"
#include "imuconv/plugin_abi.h"

#define IMUCONV_RIGHT_PERTURBED_INCREMENT(ID, VERSION, SUMMARY, BIAS_SIGN, B0, B1, B2, B3, B4) \
  namespace {                                                                                  \
  constexpr ::imuconv::BlockOrder kOrder{::imuconv::Block::B0, ::imuconv::Block::B1,           \
                                         ::imuconv::Block::B2, ::imuconv::Block::B3,           \
                                         ::imuconv::Block::B4};                                \
  using RightPerturbedIncrement =                                                              \
      ::imuconv::plugin::RightPerturbedIncrementChart<kOrder, BIAS_SIGN>;                      \
  }                                                                                            \
  IMUCONV_PLUGIN(IncrementConvention, RightPerturbedIncrement, ID, VERSION, SUMMARY)
