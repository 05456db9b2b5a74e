#include "kernels/laplacian_eigensolver.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <Spectra/SymEigsSolver.h>
#include <Eigen/CholmodSupport>

#include "kernels/blas_runtime.hpp"

namespace ggk::kernels {
namespace {

// The operator y = (L - s I)^-1 (I - N N^T) x, for Spectra's SymEigsSolver. On the
// complement of the null space it has eigenvalues 1 / (lambda - s) > 0, on the
// null space 0, so its largest eigenvalues are L's smallest non-null ones.
class DeflatedShiftInvert {
 public:
  using Scalar = double;

  DeflatedShiftInvert(const SparseColMatrix& laplacian, const RowMatrixXd& null_space, double shift)
      : null_space_(null_space) {
    SparseColMatrix shifted = laplacian;
    for (Eigen::Index i = 0; i < shifted.rows(); ++i) shifted.coeffRef(i, i) -= shift;
    factor_.compute(shifted);
  }

  bool ok() const { return factor_.info() == Eigen::Success; }
  Eigen::Index rows() const { return null_space_.rows(); }
  Eigen::Index cols() const { return null_space_.rows(); }

  void perform_op(const double* x_in, double* y_out) const {
    const Eigen::Map<const Eigen::VectorXd> x(x_in, rows());
    Eigen::VectorXd projected = x;
    if (null_space_.cols() > 0) projected.noalias() -= null_space_ * (null_space_.transpose() * x);
    Eigen::Map<Eigen::VectorXd>(y_out, rows()) = factor_.solve(projected);
  }

 private:
  const RowMatrixXd& null_space_;
  Eigen::CholmodDecomposition<Eigen::SparseMatrix<double>, Eigen::Lower> factor_;
};

// The dense path: all eigenpairs of L, the first c replaced by the null space,
// the next count - c projected off it.
void dense_eigenpairs(const SparseColMatrix& laplacian, const RowMatrixXd& null_space,
                      std::int32_t count, LaplacianEigenpairs& result) {
  const Eigen::MatrixXd dense = Eigen::MatrixXd(laplacian);
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> solver(dense);
  if (solver.info() != Eigen::Success) {
    result.message = "the dense symmetric eigensolver did not converge";
    return;
  }
  const Eigen::Index c = null_space.cols();
  for (Eigen::Index j = c; j < count; ++j) {
    Eigen::VectorXd v = solver.eigenvectors().col(j);
    if (c > 0) v -= null_space * (null_space.transpose() * v);
    result.vectors.col(j) = v;
    result.values[j] = std::max(solver.eigenvalues()[j], 0.0);
  }
  result.dense = true;
  result.ok = true;
}

void lanczos_eigenpairs(const SparseColMatrix& laplacian, const RowMatrixXd& null_space,
                        std::int32_t count, LaplacianEigenpairs& result) {
  const Eigen::Index n = laplacian.rows();
  const Eigen::Index c = null_space.cols();
  const Eigen::Index wanted = count - c;
  // s: a small negative shift, relative to the largest diagonal entry (an upper
  // bound of lambda_max / 2), so that L - s I is well conditioned.
  const double scale = laplacian.diagonal().maxCoeff();
  const double shift = -1e-3 * (scale > 0.0 ? scale : 1.0);
  DeflatedShiftInvert op(laplacian, null_space, shift);
  if (!op.ok()) {
    result.message = "CHOLMOD could not factorise L - s I (s = " + std::to_string(shift) + ")";
    return;
  }
  const Eigen::Index subspace = std::min(n, std::max<Eigen::Index>(2 * wanted + 1, wanted + 20));
  Spectra::SymEigsSolver<DeflatedShiftInvert> solver(op, wanted, subspace);
  solver.init();
  constexpr Eigen::Index kMaxRestarts = 1000;
  constexpr double kTolerance = 1e-13;
  solver.compute(Spectra::SortRule::LargestAlge, kMaxRestarts, kTolerance,
                 Spectra::SortRule::LargestAlge);
  result.operator_products = static_cast<std::int32_t>(solver.num_operations());
  if (solver.info() != Spectra::CompInfo::Successful) {
    result.message = "the Lanczos eigensolver did not converge in " + std::to_string(kMaxRestarts) +
                     " restarts (" + std::to_string(wanted) + " eigenpairs of " +
                     std::to_string(n) + " nodes)";
    return;
  }
  // Spectra sorts theta descending: lambda ascending.
  const Eigen::MatrixXd vectors = solver.eigenvectors();
  for (Eigen::Index j = 0; j < wanted; ++j) {
    Eigen::VectorXd v = vectors.col(j);
    if (c > 0) v -= null_space * (null_space.transpose() * v);
    result.vectors.col(c + j) = v;
    // The Rayleigh quotient of the final vector: as accurate as the vector allows
    // (s + 1 / theta loses digits to the shift).
    result.values[c + j] = std::max(v.dot(laplacian * v) / v.squaredNorm(), 0.0);
  }
  result.ok = true;
}

}  // namespace

void normalize_eigenvector_signs(RowMatrixXd& vectors) {
  for (Eigen::Index j = 0; j < vectors.cols(); ++j) {
    const double norm = vectors.col(j).norm();
    if (norm > 0.0) vectors.col(j) /= norm;
    const double largest = vectors.col(j).cwiseAbs().maxCoeff();
    for (Eigen::Index i = 0; i < vectors.rows(); ++i) {
      if (std::abs(vectors(i, j)) >= largest * (1.0 - 1e-9)) {
        if (vectors(i, j) < 0.0) vectors.col(j) *= -1.0;
        break;
      }
    }
  }
}

LaplacianEigenpairs smallest_laplacian_eigenpairs(const SparseColMatrix& laplacian,
                                                  const RowMatrixXd& null_space,
                                                  std::int32_t count) {
  const Eigen::Index n = laplacian.rows();
  if (laplacian.cols() != n || null_space.rows() != n || count < 0 || count > n) {
    throw std::invalid_argument("smallest_laplacian_eigenpairs: " + std::to_string(count) +
                                " eigenpairs of a " + std::to_string(laplacian.rows()) + " x " +
                                std::to_string(laplacian.cols()) + " matrix with a " +
                                std::to_string(null_space.rows()) + "-row null space");
  }
  // CHOLMOD's supernodal factor and Eigen's products reach the BLAS: one thread
  // per call (threads inside a call would compete with TBB's; measured: 0.5 s
  // instead of 1 ms for 9 pairs of a 600-node cycle on a loaded 2-core machine).
  use_calling_thread_blas();
  LaplacianEigenpairs result;
  result.values = Eigen::VectorXd::Zero(count);
  result.vectors = RowMatrixXd::Zero(n, count);
  const Eigen::Index c = std::min<Eigen::Index>(null_space.cols(), count);
  result.vectors.leftCols(c) = null_space.leftCols(c);
  if (count <= null_space.cols()) {
    result.ok = true;
  } else if (n <= kDenseLaplacianNodes || 3 * (count - c) > n - c) {
    dense_eigenpairs(laplacian, null_space, count, result);
  } else {
    lanczos_eigenpairs(laplacian, null_space, count, result);
  }
  if (!result.ok) {
    result.values.resize(0);
    result.vectors.resize(0, 0);
    return result;
  }
  normalize_eigenvector_signs(result.vectors);
  return result;
}

}  // namespace ggk::kernels
