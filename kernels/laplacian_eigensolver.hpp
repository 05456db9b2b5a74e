#pragma once
// The smallest eigenpairs of a graph Laplacian (symmetric positive semi-definite,
// with a known null space): the proto-value functions of Mahadevan & Maggioni
// (2007, JMLR 8).
//
// A graph of several components is solved component by component: L is block
// diagonal over its components (those of its non-zero off-diagonal entries), so
// its spectrum is the union of theirs and each eigenvector can be chosen on one
// component with exact zeros elsewhere. A solve of the whole L gives neither:
// Lanczos vectors leak rounding (~1e-14) into the other components, and where two
// components share an eigenvalue the solver returns an arbitrary mixture of the
// two, so a component without reward gets Q values of rounding noise instead of 0.
// Each component C (n_C nodes) gives its min(count, n_C) smallest eigenpairs as
// candidates; the `count` smallest candidates are taken, in this order (the tie
// rule): ascending eigenvalue, where eigenvalues within kEigenvalueTieTolerance
// of one another (a chain of such neighbours) are tied and ordered by component
// (numbered by its smallest node) and then by their order within it. So the
// values are ascending up to that tolerance, and the null space's exact zeros
// come first, one per component in component order.
//
// Within a component: its null-space vectors (the columns of `null_space`
// supported on it) first, with eigenvalue exactly 0; the others are the smallest
// eigenvalues of L_C on the complement: Spectra's Lanczos (SymEigsSolver) on the
// shift-inverted, deflated operator (L_C - s I)^-1 (I - N N^T), s < 0 so that
// L_C - s I is positive definite (shift-invert exactly at 0 meets a singular
// matrix), factorised once by CHOLMOD (LL^T); the largest eigenvalues theta of
// that operator give lambda = s + 1 / theta. Small problems (n_C <=
// kDenseLaplacianNodes, or the pairs wanted beyond the null space more than a
// third of n_C - c_C) take the dense path, Eigen's SelfAdjointEigenSolver. A
// connected graph is one component: L itself, as before the split.
//
// Not determined by the graph: when lambda_count and lambda_(count+1) are tied
// (within kEigenvalueTieTolerance), the eigenspace is cut and which of its
// vectors are taken is the solver's choice (the tie rule's, across components):
// `degenerate` says so, and `next_value` holds lambda_(count+1). For it, a
// component of more than count nodes adds its (count+1)-th eigenvalue to the
// candidates, value only: the dense path has it; a Lanczos component is solved a
// second time for count + 1 pairs, of which only that value is used (Lanczos
// vectors of count + 1 pairs are not bit for bit those of count, so the vectors
// taken stay those of the solve for count: a connected graph's are as before).
//
// Normalisation and sign: every vector has unit Euclidean norm, and its
// largest-magnitude entry is positive (ties, within a relative 1e-9, to the lowest
// index). Inside a repeated eigenvalue of one component the basis is the solver's,
// the same for the same input: results are bit-identical for any thread count
// (no threads inside).
//
// Thread-safety: reentrant; BLAS one thread per call (the engine arranges it).

#include <cstdint>
#include <string>
#include <vector>

#include "kernels/eigen_types.hpp"

namespace ggk::kernels {

// At most this many nodes: the dense eigensolver. Measured on grid graphs, one
// thread (bench/README.md): dense 0.7 / 1.8 / 31 ms at 100 / 144 / 400 nodes,
// Lanczos 1.0 / 1.5 / 2.6 ms for 32 pairs.
inline constexpr std::int32_t kDenseLaplacianNodes = 128;

// Two eigenvalues are tied when they differ by at most this times L's largest
// diagonal entry (1 for the normalized Laplacian, the largest degree for the
// combinatorial one; lambda_max <= 2 x it). A thousand times the Lanczos
// tolerance on theta (1e-13, relative) and far above the dense solver's error
// (~n eps ||L||), so one eigenvalue computed in two components, or twice, ties;
// far below the gaps of graphs this engine builds (a path of 10^4 nodes: ~1e-7).
inline constexpr double kEigenvalueTieTolerance = 1e-10;

struct LaplacianEigenpairs {
  bool ok = false;
  std::string message;     // why it failed; empty when ok
  Eigen::VectorXd values;  // count, ascending up to the tie tolerance (exact zeros first)
  RowMatrixXd vectors;     // n x count, column j the eigenvector of values[j]
  // The component of each pair (numbered by smallest node): column j is zero off
  // the rows with component_of_rows[row] == components[j].
  std::vector<std::int32_t> components;
  std::vector<std::int32_t> component_of_rows;  // n: the component of each row
  // lambda_(count+1), the smallest eigenvalue not taken; NaN when count = n (or
  // when the solve for it failed: then `degenerate` is false, and unknown).
  double next_value = 0.0;
  bool degenerate = false;             // lambda_count and lambda_(count+1) tied
  bool dense = false;                  // a component took the dense path
  std::int32_t operator_products = 0;  // Lanczos applications of the operators
};

// The `count` smallest eigenpairs of `laplacian` (n x n, both triangles) whose null
// space is spanned by the orthonormal columns of `null_space` (n x c), each
// supported on one component (graph_laplacian's: one per component). Throws
// std::invalid_argument when count > n, the shapes disagree or a null-space column
// spans components; a solver that does not converge is reported in `ok` /
// `message`.
LaplacianEigenpairs smallest_laplacian_eigenpairs(const SparseColMatrix& laplacian,
                                                  const RowMatrixXd& null_space,
                                                  std::int32_t count);

// The sign convention above, applied to every column: unit norm, the
// largest-magnitude entry positive (ties to the lowest index).
void normalize_eigenvector_signs(RowMatrixXd& vectors);

}  // namespace ggk::kernels
