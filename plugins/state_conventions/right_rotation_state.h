// The one-line registration of a state convention that is RightRotationChart over StateChart
// (imuconv/plugin/convention.h): R = R^ Exp(dtheta), p and v in the body frame of the
// estimate where listed in BODY_FRAME (theta is always there for a state chart) and additive
// where not, additive biases, in the block order ORDER. That list gives retract, local and the
// Jacobians, so the order and the list are all such a plugin states besides its IMUCONV_PLUGIN
// facts, each a parenthesized list of Block values:
//
//   IMUCONV_RIGHT_ROTATION_STATE("my_chart", "1.0.0", "one line summary",
//                                (Block::theta, Block::p, Block::v, Block::bg, Block::ba),
//                                (Block::theta, Block::p))
//
// This is IMUCONV_PLUGIN (plugin_abi.h) with the order, the list and the chart declared first,
// and nothing else. Use once per plugin source file, at global scope. Shared by the state
// conventions of this folder (one source file is one plugin: this header is not one).
#pragma once

#include <array>

#include "imuconv/plugin/convention.h"
#include "imuconv/plugin_abi.h"

// A parenthesized list's elements (internal to the macro below).
#define IMUCONV_RIGHT_ROTATION_LIST_(...) __VA_ARGS__

#define IMUCONV_RIGHT_ROTATION_STATE(ID, VERSION, SUMMARY, ORDER, BODY_FRAME)                   \
  namespace {                                                                                   \
  using ::imuconv::Block;                                                                       \
  constexpr ::imuconv::BlockOrder kOrder{IMUCONV_RIGHT_ROTATION_LIST_ ORDER};                   \
  constexpr std::array kBodyFrame{IMUCONV_RIGHT_ROTATION_LIST_ BODY_FRAME};                     \
  using RightRotationState =                                                                    \
      ::imuconv::plugin::RightRotationChart<::imuconv::plugin::StateChart<kOrder>, kBodyFrame>; \
  }                                                                                             \
  IMUCONV_PLUGIN(StateConvention, RightRotationState, ID, VERSION, SUMMARY)
