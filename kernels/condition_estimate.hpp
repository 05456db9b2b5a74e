#pragma once
// The reciprocal condition number of an LSPI system in the 1-norm,
// rcond = 1 / (||A||_1 ||A^-1||_1), estimated as LAPACK estimates it: ||A||_1 exactly,
// ||A^-1||_1 by dlacn2 (Higham's refinement of Hager's method, the estimator inside
// dgecon and dpocon), which needs only solves with the factor of A and of A^T
// (about five). The estimate of ||A^-1||_1 is a lower bound, in practice within a
// factor of 3 and mostly exact; so the estimated rcond is an upper bound on the true
// 1-norm rcond. On the 180 stored systems of the CI jobs it is exact for most and
// within 1.6x on 179; one LSTD-Q system, whose ||A^-1||_1 = 1/lambda comes from a
// column that only the ridge holds, is underestimated 70x (jobs/README.md,
// min_rcond). The 1-norm and 2-norm condition numbers of an n x n matrix differ by
// at most a factor of n.
//
// Internal to kernels/ (the solvers of sparse_solvers.cpp and dense_solvers.cpp).
// Thread-safety: reentrant.

#include <functional>

#include "kernels/eigen_types.hpp"

namespace ggk::kernels {

// solve(v, transposed) overwrites v with A^-1 v (transposed: A^-T v); false when
// the solve failed (the estimate is then 0).
using FactorSolve = std::function<bool(Eigen::VectorXd& v, bool transposed)>;

// ||A^-1||_1 by LAPACK's dlacn2 for an n x n A; 0 for n = 0 or a failed solve.
double inverse_one_norm_estimate(Eigen::Index n, const FactorSolve& solve);

// 1 / (a_one_norm * inverse_one_norm), 0 when either is 0 or not finite.
double reciprocal_condition(double a_one_norm, double inverse_one_norm);

// ||A||_1 (the largest column sum of |a_ij|) of a sparse matrix, or of the
// symmetric matrix whose lower triangle `lower` holds.
double one_norm(const SparseColMatrix& a);
double symmetric_one_norm(const SparseColMatrix& lower);

}  // namespace ggk::kernels
