#pragma once
// Dense direct solvers for the LSPI systems (LAPACK through the BLAS the engine
// runs: Debian's OpenBLAS), with the same failure detection and the same report
// as the sparse solvers (sparse_solvers.hpp), so either kind can evaluate a fit.
//
// DenseSymmetricSolver: Cholesky LL^T (dpotrf / dpotrs), lower triangle read.
// DenseLuSolver: LU with partial pivoting (dgetrf / dgetrs), in block triangular
// form when given a block size: the matrix is read as nb x nb blocks, the
// strongly connected components of its block graph (i -> j when A_ij != 0) are
// solved one after the other by forward substitution, each by its own LU. Pivoting
// then never mixes rows of blocks that the structure keeps apart, so unknowns that
// are zero in exact arithmetic (a block whose right-hand side is zero and which
// depends only on such blocks) come out as exact zeros, as from UMFPACK, instead
// of pivoting residue (LSPI's greedy step breaks exact ties by the lowest action;
// residue would break them at random). One component holding all blocks is a plain
// LU of the whole matrix.
// A matrix that is not positive definite / is singular, a reciprocal condition
// estimate under min_rcond, or a non-finite solution is reported and the solution
// is left untouched. The estimate is LAPACK's reciprocal 1-norm condition estimate
// on the factor (condition_estimate.hpp): dpocon for the Cholesky factor; for the
// LU, dgecon's estimator (dlacn2) over the whole block triangular factor. The
// sparse solvers estimate the same number, so min_rcond means one thing for both
// kinds.
//
// Why dense at all: the LSPI systems of Gaussian kernels are mostly dense (each
// p x p action block is a sum of kernel outer products), and on a dense matrix a
// sparse factorisation pays for index bookkeeping, memory growth and page faults
// that LAPACK's blocked dpotrf / dgetrf do not (bench/lspi_benchmark.cpp,
// BM_FitLspi: linear_algebra sparse vs dense).
//
// Thread-safety: none; one solver per task. BLAS must be single-threaded inside
// tasks (the engine arranges it).

#include <vector>

#include "kernels/eigen_types.hpp"
#include "kernels/sparse_solvers.hpp"

namespace ggk::kernels {

class DenseSymmetricSolver {
 public:
  explicit DenseSymmetricSolver(SolverSettings settings = {});

  // Solves (A + ridge I) x = b; only the lower triangle of A is read.
  // report.reused_analysis is always false (a dense factorisation has none).
  SolveReport solve(const Eigen::MatrixXd& a, double ridge, const Eigen::VectorXd& b,
                    Eigen::VectorXd& x);

 private:
  SolverSettings settings_;
  Eigen::MatrixXd factor_;  // reused from call to call: no fresh pages per solve
  Eigen::VectorXd work_;    // 64-byte aligned (kernels/CMakeLists.txt says why)
  std::vector<int> iwork_;
};

class DenseLuSolver {
 public:
  explicit DenseLuSolver(SolverSettings settings = {});

  // Solves (A + ridge I) x = b; block_size > 0 dividing the order: in block
  // triangular form of blocks of that size. report.reused_analysis is always false.
  SolveReport solve(const Eigen::MatrixXd& a, double ridge, const Eigen::VectorXd& b,
                    Eigen::VectorXd& x, Eigen::Index block_size = 0);

 private:
  bool block_solve(const Eigen::MatrixXd& a, Eigen::Index block_size,
                   const std::vector<std::vector<bool>>& depends,
                   const std::vector<std::vector<Eigen::Index>>& components, Eigen::VectorXd& v,
                   bool transposed) const;

  SolverSettings settings_;
  std::vector<Eigen::MatrixXd> factors_;  // one per component, reused from call to call
  std::vector<std::vector<int>> pivots_;
};

}  // namespace ggk::kernels
