#include "kernels/dense_solvers.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>

#include "kernels/blas_runtime.hpp"

// LAPACK's Fortran entry points (reference LAPACK and OpenBLAS alike; 32-bit
// integers as Debian builds them).
extern "C" {
void dpotrf_(const char* uplo, const int* n, double* a, const int* lda, int* info);
void dpotrs_(const char* uplo, const int* n, const int* nrhs, const double* a, const int* lda,
             double* b, const int* ldb, int* info);
void dgetrf_(const int* m, const int* n, double* a, const int* lda, int* ipiv, int* info);
void dgetrs_(const char* trans, const int* n, const int* nrhs, const double* a, const int* lda,
             const int* ipiv, double* b, const int* ldb, int* info);
}

namespace ggk::kernels {

namespace {

enum class Part { lower, full };

bool check_input(const Eigen::MatrixXd& a, Part part, double ridge, const Eigen::VectorXd& b,
                 SolveReport& report) {
  if (a.rows() != a.cols() || a.rows() != b.size()) {
    std::ostringstream message;
    message << "system shape mismatch: A is " << a.rows() << " x " << a.cols() << ", b has "
            << b.size() << " entries";
    report.message = message.str();
    return false;
  }
  if (a.rows() > std::numeric_limits<int>::max()) {
    report.message = "system too large for LAPACK's 32-bit indices";
    return false;
  }
  const bool finite = part == Part::full
                          ? a.allFinite()
                          : a.triangularView<Eigen::Lower>().toDenseMatrix().allFinite();
  if (!finite || !std::isfinite(ridge)) {
    report.message = "system matrix has non-finite entries";
    return false;
  }
  if (!b.allFinite()) {
    report.message = "right-hand side has non-finite entries";
    return false;
  }
  return true;
}

// factor = A + ridge I (the part the factorisation reads).
void load(const Eigen::MatrixXd& a, Part part, double ridge, Eigen::MatrixXd& factor) {
  factor.resize(a.rows(), a.cols());
  if (part == Part::full) {
    factor = a;
  } else {
    factor.triangularView<Eigen::Lower>() = a.triangularView<Eigen::Lower>();
  }
  factor.diagonal().array() += ridge;
}

// The common tail: conditioning, finiteness and the residual; x is written only
// when every check passes.
template <class Apply>
void finish(double rcond, double min_rcond, Eigen::VectorXd&& candidate, const Eigen::VectorXd& b,
            const Apply& apply, SolveReport& report, Eigen::VectorXd& x) {
  report.rcond = rcond;
  if (!(report.rcond >= min_rcond)) {
    std::ostringstream message;
    message << "ill-conditioned system: reciprocal condition estimate " << report.rcond
            << " < min_rcond " << min_rcond;
    report.message = message.str();
    return;
  }
  if (!candidate.allFinite()) {
    report.message = "solution has non-finite entries";
    return;
  }
  const double b_norm = b.norm();
  const Eigen::VectorXd residual = apply(candidate) - b;
  report.relative_residual = b_norm > 0.0 ? residual.norm() / b_norm : residual.norm();
  report.ok = true;
  x = std::move(candidate);
}

}  // namespace

DenseSymmetricSolver::DenseSymmetricSolver(SolverSettings settings) : settings_(settings) {
  use_calling_thread_blas();
}

SolveReport DenseSymmetricSolver::solve(const Eigen::MatrixXd& a, double ridge,
                                        const Eigen::VectorXd& b, Eigen::VectorXd& x) {
  SolveReport report;
  if (!check_input(a, Part::lower, ridge, b, report)) return report;
  load(a, Part::lower, ridge, factor_);
  const int n = static_cast<int>(a.rows());
  const int lda = std::max(1, n);
  int info = 0;
  dpotrf_("L", &n, factor_.data(), &lda, &info);
  if (info != 0) {
    std::ostringstream message;
    if (info > 0) {
      message << "LAPACK dpotrf: matrix is not positive definite (failed at column " << info - 1
              << " of " << n << ")";
    } else {
      message << "LAPACK dpotrf: argument " << -info << " is invalid";
    }
    report.message = message.str();
    return report;
  }
  double rcond = 0.0;
  if (n > 0) {
    const auto diagonal = factor_.diagonal();
    const double ratio = diagonal.minCoeff() / diagonal.maxCoeff();
    rcond = ratio * ratio;  // cholmod_rcond's estimate for an LL^T factor
  }
  Eigen::VectorXd candidate = b;
  const int one = 1;
  dpotrs_("L", &n, &one, factor_.data(), &lda, candidate.data(), &lda, &info);
  finish(
      rcond, settings_.min_rcond, std::move(candidate), b,
      [&](const Eigen::VectorXd& v) {
        Eigen::VectorXd product = a.selfadjointView<Eigen::Lower>() * v;
        product += ridge * v;
        return product;
      },
      report, x);
  return report;
}

DenseLuSolver::DenseLuSolver(SolverSettings settings) : settings_(settings) {
  use_calling_thread_blas();
}

SolveReport DenseLuSolver::solve(const Eigen::MatrixXd& a, double ridge, const Eigen::VectorXd& b,
                                 Eigen::VectorXd& x) {
  SolveReport report;
  if (!check_input(a, Part::full, ridge, b, report)) return report;
  load(a, Part::full, ridge, factor_);
  const int n = static_cast<int>(a.rows());
  const int lda = std::max(1, n);
  pivots_.resize(static_cast<std::size_t>(n));
  int info = 0;
  dgetrf_(&n, &n, factor_.data(), &lda, pivots_.data(), &info);
  if (info < 0) {
    report.message = "LAPACK dgetrf: argument " + std::to_string(-info) + " is invalid";
    return report;
  }
  if (info > 0) {
    report.message = "LAPACK dgetrf: matrix is singular (U(" + std::to_string(info - 1) + ", " +
                     std::to_string(info - 1) + ") is exactly zero)";
    return report;
  }
  double rcond = 0.0;
  if (n > 0) {
    const Eigen::VectorXd magnitudes = factor_.diagonal().cwiseAbs();
    rcond = magnitudes.minCoeff() / magnitudes.maxCoeff();  // UMFPACK_RCOND's estimate
  }
  Eigen::VectorXd candidate = b;
  const int one = 1;
  dgetrs_("N", &n, &one, factor_.data(), &lda, pivots_.data(), candidate.data(), &lda, &info);
  finish(
      rcond, settings_.min_rcond, std::move(candidate), b,
      [&](const Eigen::VectorXd& v) {
        Eigen::VectorXd product = a * v;
        product += ridge * v;
        return product;
      },
      report, x);
  return report;
}

}  // namespace ggk::kernels
