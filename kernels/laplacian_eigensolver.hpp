#pragma once
// The smallest eigenpairs of a graph Laplacian (symmetric positive semi-definite,
// with a known null space): the proto-value functions of Mahadevan & Maggioni
// (2007, JMLR 8).
//
// The c null-space vectors given come first, with eigenvalue exactly 0 (a graph of
// c components has c zero eigenvalues, one indicator-like vector each: none is
// "dropped"). The other count - c pairs are the smallest eigenvalues of L on the
// orthogonal complement: Spectra's Lanczos (SymEigsSolver) on the shift-inverted,
// deflated operator (L - s I)^-1 (I - N N^T), s < 0 so that L - s I is positive
// definite (shift-invert exactly at 0 meets a singular matrix), factorised once by
// CHOLMOD (LL^T); the largest eigenvalues theta of that operator give
// lambda = s + 1 / theta. Small problems (n <= kDenseLaplacianNodes, or count - c
// more than a third of n - c) take the dense path, Eigen's SelfAdjointEigenSolver.
//
// Normalisation and sign: every vector has unit Euclidean norm, and its
// largest-magnitude entry is positive (ties, within a relative 1e-9, to the lowest
// index). Inside a repeated eigenvalue the basis is the solver's, the same for the
// same input: results are bit-identical for any thread count (no threads inside).
//
// Thread-safety: reentrant; BLAS one thread per call (the engine arranges it).

#include <cstdint>
#include <string>

#include "kernels/eigen_types.hpp"

namespace ggk::kernels {

// At most this many nodes: the dense eigensolver. Measured on grid graphs, one
// thread (bench/README.md): dense 0.7 / 1.8 / 31 ms at 100 / 144 / 400 nodes,
// Lanczos 1.0 / 1.5 / 2.6 ms for 32 pairs.
inline constexpr std::int32_t kDenseLaplacianNodes = 128;

struct LaplacianEigenpairs {
  bool ok = false;
  std::string message;                 // why it failed; empty when ok
  Eigen::VectorXd values;              // count, ascending (the null space's exact zeros first)
  RowMatrixXd vectors;                 // n x count, column j the eigenvector of values[j]
  bool dense = false;                  // the dense path was taken
  std::int32_t operator_products = 0;  // Lanczos applications of the operator
};

// The `count` smallest eigenpairs of `laplacian` (n x n, both triangles) whose null
// space is spanned by the orthonormal columns of `null_space` (n x c). Throws
// std::invalid_argument when count > n or the shapes disagree; a solver that does
// not converge is reported in `ok` / `message`.
LaplacianEigenpairs smallest_laplacian_eigenpairs(const SparseColMatrix& laplacian,
                                                  const RowMatrixXd& null_space,
                                                  std::int32_t count);

// The sign convention above, applied to every column: unit norm, the
// largest-magnitude entry positive (ties to the lowest index).
void normalize_eigenvector_signs(RowMatrixXd& vectors);

}  // namespace ggk::kernels
