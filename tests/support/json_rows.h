// A matrix as JSON rows [[...], ...], the layout of every matrix in imuconv's documents, for
// tests that write a changed matrix into an input: the outputs' own writer (matrix_rows.h), the
// inverse of JsonMatrix (imuconv_test.h).
#pragma once

#include "imuconv/pipeline/matrix_rows.h"

namespace imuconv::test {

inline nlohmann::json JsonRows(const Eigen::MatrixXd& m) { return pipeline::MatrixToJson(m); }

}  // namespace imuconv::test
