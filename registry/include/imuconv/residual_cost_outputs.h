// A residual plugin's cost declaration (residual_cost_spec.h) checked and resolved once, and
// the ResidualSink that keeps, of everything the plugin writes, the outputs the declaration
// names: the residual, the weighting matrix and the Jacobians' columns. The plugin is
// untrusted: every string is bounded, every value checked, every problem a message naming the
// plugin and the output. In the registry, not in imuconv::ceres, because two places need it and
// only one has Ceres: NativeResidualFactor builds its cost from it, and `imuconv plugins
// --check` checks a residual plugin's declaration against what its evaluate() writes.
#pragma once

#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "imuconv/registry.h"
#include "imuconv/residual_factor.h"

namespace imuconv {

/// Output names and convention ids of a cost declaration are short; a longer string (or one
/// without its terminating NUL within this bound) is a broken declaration, not one to read on.
inline constexpr std::size_t kMaxCostNameLength = 256;

/// `s` read as a name of a cost declaration into `out`: false for null, empty, or longer than
/// kMaxCostNameLength (nothing past that bound is read).
IMUCONV_API bool ReadCostName(const char* s, std::string& out);

using RowMajorMatrixXd = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

/// Three Jacobian columns: output `output` (an index into ResidualCostOutputs::names), columns
/// [first_column, first_column + 3), at `offset` of the state convention's tangent.
struct ResidualJacobianPlacement {
  int output = -1;
  int first_column = 0;
  int offset = 0;
};

/// The declaration, checked: the outputs to keep (the residual first, then the weighting matrix
/// if any, then the Jacobian matrices, each once) and where each Jacobian block goes.
struct ResidualCostOutputs {
  std::string id;                ///< the plugin's id, for messages
  int n = 0;                     ///< the residual's dimension
  std::string state_convention;  ///< the convention the Jacobian columns are in
  ResidualWeighting weighting = ResidualWeighting::SqrtInformation;
  std::vector<std::string> names;  ///< [0] residual, [1] weighting matrix (if named), matrices
  /// Per output: the columns it must have at least (1 for the residual, a vector).
  std::vector<int> min_cols;
  int weighting_output = -1;  ///< index of the weighting matrix in names, or -1
  std::vector<ResidualJacobianPlacement> start, end;
};

/// Checks `factor`'s cost_spec() (non-null, bounded strings, known convention and weighting,
/// each tangent block at most once per state) against `reg`. Throws imuconv::Error naming the
/// plugin.
IMUCONV_API ResidualCostOutputs ResolveResidualCost(const Registry& reg,
                                                    const ResidualFactor& factor);

/// What one evaluation wrote, of the declared outputs.
struct ResidualOutputValues {
  std::vector<RowMajorMatrixXd> values;  ///< by ResidualCostOutputs::names (a vector as one column)
  std::vector<bool> written;
};

/// Keeps the declared outputs; the first problem (a null name, an output written twice, a size
/// other than declared, a non-finite number) is recorded and what follows is ignored.
class IMUCONV_API ResidualCostOutputSink final : public ResidualSink {
 public:
  ResidualCostOutputSink(const ResidualCostOutputs& outputs, ResidualOutputValues& into);
  void begin_group(const char* name) noexcept override;
  void end_group() noexcept override;
  void vector(const char* name, const double* values, int size) noexcept override;
  void matrix(const char* name, const double* row_major, int rows, int cols) noexcept override;
  void mahalanobis_squared(double) noexcept override {}
  /// The first problem, or "" (then every declared output was also checked to be written).
  std::string Finish() const;

 private:
  /// The declared output at the open group's `name`, or -1.
  int Find(const char* name);
  void Keep(const char* name, const double* data, int rows, int cols, bool is_vector) noexcept;
  const ResidualCostOutputs& outputs_;
  ResidualOutputValues& into_;
  std::string path_;                 ///< the open groups, each followed by '/'
  std::vector<std::size_t> groups_;  ///< path_'s length before each open group
  std::string problem_;
};

/// Runs the plugin on (m, x_s, x_e) and reads its declared outputs; "" or the problem (its
/// Status message, or the sink's), prefixed by nothing: the caller names the plugin.
IMUCONV_API std::string EvaluateResidualCost(const ResidualFactor& factor,
                                             const ResidualCostOutputs& outputs,
                                             const Preintegrated& m, const ImuState& x_s,
                                             const ImuState& x_e, const Vec3& gravity,
                                             ResidualOutputValues& values) noexcept;

/// The residual's Jacobian by one state, in the declared convention's tangent order (n x 15):
/// the declared columns at their blocks' offsets, zero elsewhere.
IMUCONV_API void AssembleResidualJacobian(const ResidualCostOutputs& outputs,
                                          const ResidualOutputValues& values,
                                          const std::vector<ResidualJacobianPlacement>& blocks,
                                          Eigen::MatrixXd& H);

}  // namespace imuconv
