// The order of a convention's five 3-blocks, declared once as a constexpr value from which
// both the labels ("p", "theta", ...) and the offsets (0, 3, ..., 12) derive.
//
// A perturbation vector of a convention is [b0, b1, b2, b3, b4] with each b a 3-vector, and
// which quantity each block perturbs is part of the convention (J. Huai, "IMU Propagation as
// Preintegration", section 2.1: x = x^ [+]^p dx^p). States use p, theta, v, bg, ba; increments
// use the same names for dp, dtheta, dv, dbg, dba.
#pragma once

#include <array>
#include <iterator>
#include <string_view>

#include "imuconv/enum_name.h"

namespace imuconv {

/// One 3-block of the 15-dimensional perturbation.
enum class Block : unsigned char { p, theta, v, bg, ba };

constexpr int kBlockCount = 5;

namespace detail {
inline constexpr const char* kBlockNames[] = {"p", "theta", "v", "bg", "ba"};  // Block's order
static_assert(std::size(kBlockNames) == kBlockCount, "a name per block");
}  // namespace detail

/// "p", "theta", "v", "bg", "ba"; nullptr for a value outside the enum (a hostile plugin).
constexpr const char* BlockName(Block b) noexcept {
  return EnumName(b, Block::p, detail::kBlockNames, nullptr);
}

/// Labels of the five 3-blocks in a convention's order, e.g. {"theta","p","v","ba","bg"}.
using BlockLabels = std::array<const char*, kBlockCount>;

/// A convention's block order. Plugins declare one as constexpr:
///   constexpr BlockOrder kOrder{Block::theta, Block::p, Block::v, Block::ba, Block::bg};
struct BlockOrder {
  std::array<Block, kBlockCount> blocks;

  constexpr BlockOrder(Block b0, Block b1, Block b2, Block b3, Block b4) noexcept
      : blocks{b0, b1, b2, b3, b4} {}

  /// Offset of block b in a 15-vector of this order (0, 3, ..., 12); -1 if b is absent.
  constexpr int offset(Block b) const noexcept {
    for (int i = 0; i < kBlockCount; ++i)
      if (blocks[i] == b) return 3 * i;
    return -1;
  }
  /// True when the five blocks are p, theta, v, bg and ba, each once.
  constexpr bool is_permutation() const noexcept {
    for (int k = 0; k < kBlockCount; ++k)
      if (offset(static_cast<Block>(k)) < 0) return false;
    return true;
  }
  constexpr BlockLabels labels() const noexcept {
    return {BlockName(blocks[0]), BlockName(blocks[1]), BlockName(blocks[2]), BlockName(blocks[3]),
            BlockName(blocks[4])};
  }
  constexpr bool operator==(const BlockOrder& o) const noexcept {
    for (int i = 0; i < kBlockCount; ++i)
      if (blocks[i] != o.blocks[i]) return false;
    return true;
  }
};

/// The block named `label`; false when no block has that name.
constexpr bool BlockFromName(std::string_view label, Block& out) noexcept {
  for (int k = 0; k < kBlockCount; ++k)
    if (label == BlockName(static_cast<Block>(k))) {
      out = static_cast<Block>(k);
      return true;
    }
  return false;
}

/// The state reference chart `left`: [p, theta, v, bg, ba]. (inline: one object in every
/// translation unit, so that a chart template instantiated on it in a header is one type.)
inline constexpr BlockOrder kLeftOrder{Block::p, Block::theta, Block::v, Block::bg, Block::ba};
/// The increment reference chart `preint_reference`: [theta, p, v, bg, ba].
inline constexpr BlockOrder kPreintReferenceOrder{Block::theta, Block::p, Block::v, Block::bg,
                                                  Block::ba};

static_assert(kLeftOrder.is_permutation() && kPreintReferenceOrder.is_permutation());
static_assert(kLeftOrder.offset(Block::bg) == 9 && kPreintReferenceOrder.offset(Block::theta) == 0);

}  // namespace imuconv
