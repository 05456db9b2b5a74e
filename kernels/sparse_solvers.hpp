#pragma once
// Sparse direct solvers for the LSPI systems, with failure detection.
//
// SymmetricSolver: CHOLMOD (supernodal or simplicial LL^T, chosen by CHOLMOD) for
// symmetric positive definite systems. NonsymmetricSolver: UMFPACK LU. Both keep
// the symbolic analysis of the last matrix and reuse it while the sparsity pattern
// is unchanged. A matrix that is not positive definite / is singular, a reciprocal
// condition estimate under min_rcond, or a non-finite solution is reported in the
// SolveReport and the solution is left untouched: no NaN ever escapes.
//
// Thread-safety: none; one solver per task. BLAS must be single-threaded inside
// tasks (the engine arranges it).

#include <memory>
#include <string>

#include "kernels/eigen_types.hpp"

namespace ggk::kernels {

struct SolveReport {
  bool ok = false;
  std::string message;             // why it failed; empty when ok
  double rcond = 0.0;              // LAPACK's reciprocal 1-norm condition estimate of A
                                   // (condition_estimate.hpp)
  double relative_residual = 0.0;  // ||A x - b|| / ||b||
  bool reused_analysis = false;    // the symbolic analysis of the previous call was reused
};

struct SolverSettings {
  // Systems with a reciprocal condition estimate below this are reported as
  // ill-conditioned. The estimate is LAPACK's reciprocal 1-norm condition number
  // estimate, 1 / (||A||_1 est(||A^-1||_1)), for every solver, sparse or dense
  // (condition_estimate.hpp).
  double min_rcond = 1e-14;
};

class SymmetricSolver {
 public:
  explicit SymmetricSolver(SolverSettings settings = {});
  ~SymmetricSolver();
  SymmetricSolver(SymmetricSolver&&) noexcept;
  SymmetricSolver& operator=(SymmetricSolver&&) noexcept;

  // Solves A x = b; only the lower triangle of A is read.
  SolveReport solve(const SparseColMatrix& a, const Eigen::VectorXd& b, Eigen::VectorXd& x);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

class NonsymmetricSolver {
 public:
  explicit NonsymmetricSolver(SolverSettings settings = {});
  ~NonsymmetricSolver();
  NonsymmetricSolver(NonsymmetricSolver&&) noexcept;
  NonsymmetricSolver& operator=(NonsymmetricSolver&&) noexcept;

  SolveReport solve(const SparseColMatrix& a, const Eigen::VectorXd& b, Eigen::VectorXd& x);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace ggk::kernels
