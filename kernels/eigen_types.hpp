#pragma once
// Eigen types shared across ggk. Index type of sparse matrices is int32 throughout
// (CHOLMOD and UMFPACK "int" interfaces); a feature table with more than 2^31
// non-zeros is out of scope.

#include <cstdint>

#include <Eigen/Dense>
#include <Eigen/Sparse>

namespace ggk::kernels {

using RowMatrixXd = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
using SparseRowMatrix = Eigen::SparseMatrix<double, Eigen::RowMajor, std::int32_t>;
using SparseColMatrix = Eigen::SparseMatrix<double, Eigen::ColMajor, std::int32_t>;

}  // namespace ggk::kernels
