// A residual plugin's cost spec (imuconv/residual_cost_spec.h) written one Jacobian output a
// line: the matrix's path and the state blocks its 3-column groups differentiate by, from
// column 0 on, in column order (VINS-Fusion's jacobian_speedbias_i: v, ba, bg). The spec's
// entries, one per block with its first column (0, 3, 6), follow from that, in the order the
// outputs and their blocks are listed. More than five blocks for one state does not compile.
// Shared by the residual plugins of this folder (one source file is one plugin: this header
// is not one).
#pragma once

#include <initializer_list>

#include "imuconv/residual_cost_spec.h"

namespace imuconv::plugin {

/// One Jacobian output of a factor: its path ("raw/jacobian_pose_i") and the blocks of the
/// state tangent its columns [0, 3), [3, 6), [6, 9) differentiate by, as many as are listed.
struct JacobianBlocks {
  template <class... Blocks>
  constexpr JacobianBlocks(const char* matrix_path, Blocks... in_column_order)
      : matrix(matrix_path), blocks{in_column_order...}, count(sizeof...(Blocks)) {}
  const char* matrix;
  Block blocks[3];
  int count;
};

/// The entries of a spec's `start` or `end` for these outputs; entries not filled stay unused
/// (matrix nullptr).
constexpr void FillJacobianColumns(std::initializer_list<JacobianBlocks> outputs,
                                   ResidualJacobianColumns (&columns)[kResidualJacobianBlocks]) {
  int i = 0;
  for (const JacobianBlocks& o : outputs)
    for (int k = 0; k < o.count; ++k) columns[i++] = {o.matrix, 3 * k, o.blocks[k]};
}

/// The cost spec whose derivatives by x_s are the outputs `start` and by x_e `end`.
constexpr ResidualCostSpec CostSpecOf(const char* residual, const char* state_convention,
                                      ResidualWeighting weighting, const char* weighting_matrix,
                                      std::initializer_list<JacobianBlocks> start,
                                      std::initializer_list<JacobianBlocks> end) {
  ResidualCostSpec spec{residual, state_convention, weighting, weighting_matrix, {}, {}};
  FillJacobianColumns(start, spec.start);
  FillJacobianColumns(end, spec.end);
  return spec;
}

}  // namespace imuconv::plugin
