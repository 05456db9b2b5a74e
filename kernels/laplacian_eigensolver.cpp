#include "kernels/laplacian_eigensolver.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <stdexcept>
#include <vector>

#include <Spectra/SymEigsSolver.h>
#include <Eigen/CholmodSupport>

#include "kernels/blas_runtime.hpp"
#include "kernels/csr_graph.hpp"

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
// the next count - c projected off it; lambda_(count+1) comes with them.
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
  if (count < laplacian.rows()) result.next_value = std::max(solver.eigenvalues()[count], 0.0);
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

// The components of L's graph: rows joined by a non-zero off-diagonal entry
// (graph_laplacian stores no edge of zero affinity, so these are the graph's).
ConnectedComponents laplacian_components(const SparseColMatrix& laplacian) {
  CsrGraph graph;
  graph.num_nodes = static_cast<std::int32_t>(laplacian.cols());
  graph.indptr.assign(1, 0);
  for (Eigen::Index j = 0; j < laplacian.outerSize(); ++j) {
    for (SparseColMatrix::InnerIterator it(laplacian, j); it; ++it) {
      if (it.row() == j || it.value() == 0.0) continue;
      graph.indices.push_back(static_cast<std::int32_t>(it.row()));
      graph.weights.push_back(1.0);
    }
    graph.indptr.push_back(static_cast<std::int64_t>(graph.indices.size()));
  }
  return connected_components(graph);
}

// The eigenpairs of one connected block: its null space (count <= c), else the
// dense or the Lanczos path. Vectors not yet normalised; next_value set only by
// the dense path (and when the null space alone outnumbers count).
LaplacianEigenpairs connected_eigenpairs(const SparseColMatrix& laplacian,
                                         const RowMatrixXd& null_space, std::int32_t count) {
  const Eigen::Index n = laplacian.rows();
  LaplacianEigenpairs result;
  result.next_value = std::numeric_limits<double>::quiet_NaN();
  result.values = Eigen::VectorXd::Zero(count);
  result.vectors = RowMatrixXd::Zero(n, count);
  const Eigen::Index c = std::min<Eigen::Index>(null_space.cols(), count);
  result.vectors.leftCols(c) = null_space.leftCols(c);
  if (count <= null_space.cols()) {
    if (count < null_space.cols()) result.next_value = 0.0;
    result.ok = true;
  } else if (n <= kDenseLaplacianNodes || 3 * (count - c) > n - c) {
    dense_eigenpairs(laplacian, null_space, count, result);
  } else {
    lanczos_eigenpairs(laplacian, null_space, count, result);
  }
  return result;
}

// One component's block of L and its null-space columns, rows in id order.
struct ComponentProblem {
  std::vector<std::int32_t> rows;
  std::vector<Eigen::Index> null_columns;
  SparseColMatrix matrix;
  RowMatrixXd null_space;
};

std::vector<ComponentProblem> component_problems(const SparseColMatrix& laplacian,
                                                 const RowMatrixXd& null_space,
                                                 const ConnectedComponents& components) {
  std::vector<ComponentProblem> problems(static_cast<std::size_t>(components.count));
  std::vector<std::int32_t> local_of(components.labels.size());
  for (std::size_t r = 0; r < components.labels.size(); ++r) {
    ComponentProblem& problem = problems[static_cast<std::size_t>(components.labels[r])];
    local_of[r] = static_cast<std::int32_t>(problem.rows.size());
    problem.rows.push_back(static_cast<std::int32_t>(r));
  }
  for (Eigen::Index k = 0; k < null_space.cols(); ++k) {
    std::int32_t label = -1;
    for (Eigen::Index r = 0; r < null_space.rows(); ++r) {
      if (null_space(r, k) == 0.0) continue;
      const std::int32_t row_label = components.labels[static_cast<std::size_t>(r)];
      if (label >= 0 && row_label != label) {
        throw std::invalid_argument("smallest_laplacian_eigenpairs: null-space column " +
                                    std::to_string(k) + " spans components " +
                                    std::to_string(label) + " and " + std::to_string(row_label));
      }
      label = row_label;
    }
    if (label < 0) {
      throw std::invalid_argument("smallest_laplacian_eigenpairs: null-space column " +
                                  std::to_string(k) + " is zero");
    }
    problems[static_cast<std::size_t>(label)].null_columns.push_back(k);
  }
  for (std::size_t label = 0; label < problems.size(); ++label) {
    ComponentProblem& problem = problems[label];
    const auto size = static_cast<Eigen::Index>(problem.rows.size());
    std::vector<Eigen::Triplet<double, std::int32_t>> entries;
    for (Eigen::Index j = 0; j < size; ++j) {
      for (SparseColMatrix::InnerIterator it(laplacian, problem.rows[static_cast<std::size_t>(j)]);
           it; ++it) {
        const auto row = static_cast<std::size_t>(it.row());
        // An entry to another component is an explicit zero (laplacian_components).
        if (components.labels[row] != static_cast<std::int32_t>(label)) continue;
        entries.emplace_back(local_of[row], static_cast<std::int32_t>(j), it.value());
      }
    }
    problem.matrix.resize(size, size);
    problem.matrix.setFromTriplets(entries.begin(), entries.end());
    problem.matrix.makeCompressed();
    problem.null_space.resize(size, static_cast<Eigen::Index>(problem.null_columns.size()));
    for (std::size_t k = 0; k < problem.null_columns.size(); ++k) {
      for (Eigen::Index j = 0; j < size; ++j) {
        problem.null_space(j, static_cast<Eigen::Index>(k)) =
            null_space(problem.rows[static_cast<std::size_t>(j)], problem.null_columns[k]);
      }
    }
  }
  return problems;
}

// A candidate eigenpair: pair `index` of component `component`. A component with
// more nodes than pairs asked adds its next eigenvalue, value only (index =
// its pairs' count): lambda_(count+1) may be it, and it joins the ties.
struct Candidate {
  double value;
  std::int32_t component;
  std::int32_t index;
};

// The tie rule (header): ascending value; a chain of values each within `tie`
// of the one before is one group, ordered by (component, index). Then each
// component's candidates are relabelled in index order along the result, so that
// every prefix takes each component's pairs as a prefix of its own (a no-op
// unless a solver's values are out of order by more than `tie`). `group` gets
// each position's group.
void order_candidates(std::vector<Candidate>& candidates,
                      const std::vector<std::vector<double>>& values_of, double tie,
                      std::vector<std::int32_t>& group) {
  const auto by_value = [](const Candidate& a, const Candidate& b) {
    if (a.value != b.value) return a.value < b.value;
    if (a.component != b.component) return a.component < b.component;
    return a.index < b.index;
  };
  const auto by_component = [](const Candidate& a, const Candidate& b) {
    if (a.component != b.component) return a.component < b.component;
    return a.index < b.index;
  };
  std::sort(candidates.begin(), candidates.end(), by_value);
  group.assign(candidates.size(), 0);
  std::size_t start = 0;
  std::int32_t groups = 0;
  for (std::size_t i = 1; i <= candidates.size(); ++i) {
    if (i < candidates.size() && candidates[i].value - candidates[i - 1].value <= tie) continue;
    std::sort(candidates.begin() + static_cast<std::ptrdiff_t>(start),
              candidates.begin() + static_cast<std::ptrdiff_t>(i), by_component);
    for (std::size_t k = start; k < i; ++k) group[k] = groups;
    ++groups;
    start = i;
  }
  std::vector<std::int32_t> next_index(values_of.size(), 0);
  for (Candidate& candidate : candidates) {
    const auto c = static_cast<std::size_t>(candidate.component);
    candidate.index = next_index[c]++;
    candidate.value = values_of[c][static_cast<std::size_t>(candidate.index)];
  }
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
  const ConnectedComponents components = laplacian_components(laplacian);
  std::vector<ComponentProblem> problems;
  if (components.count > 1) problems = component_problems(laplacian, null_space, components);
  const double tie = kEigenvalueTieTolerance * (n > 0 ? laplacian.diagonal().maxCoeff() : 0.0);

  // Each component's candidates, and its next eigenvalue when it has more
  // nodes than candidates. A connected graph is solved as L itself.
  LaplacianEigenpairs result;
  std::vector<LaplacianEigenpairs> solved(static_cast<std::size_t>(components.count));
  std::vector<std::vector<double>> values_of(solved.size());
  std::vector<Candidate> candidates;
  bool next_known = true;
  for (std::size_t c = 0; c < solved.size(); ++c) {
    const SparseColMatrix& matrix = problems.empty() ? laplacian : problems[c].matrix;
    const RowMatrixXd& nulls = problems.empty() ? null_space : problems[c].null_space;
    const Eigen::Index size = matrix.rows();
    const auto wanted = static_cast<std::int32_t>(std::min<Eigen::Index>(count, size));
    solved[c] = connected_eigenpairs(matrix, nulls, wanted);
    LaplacianEigenpairs& pairs = solved[c];
    result.operator_products += pairs.operator_products;
    result.dense = result.dense || pairs.dense;
    if (!pairs.ok) {
      result.message = pairs.message;
      if (components.count > 1) {
        result.message += " (component " + std::to_string(c) + " of " +
                          std::to_string(components.count) + ", " + std::to_string(size) +
                          " nodes)";
      }
      return result;
    }
    values_of[c].assign(pairs.values.data(), pairs.values.data() + pairs.values.size());
    for (std::int32_t j = 0; j < wanted; ++j) {
      candidates.push_back(
          {values_of[c][static_cast<std::size_t>(j)], static_cast<std::int32_t>(c), j});
    }
    if (wanted == size) continue;  // every eigenvalue of the component is a candidate
    if (std::isnan(pairs.next_value)) {
      // Lanczos gives no more than it is asked for: one more pair, on its own, for
      // its value (the vectors taken stay those of `wanted` pairs).
      const LaplacianEigenpairs more = connected_eigenpairs(matrix, nulls, wanted + 1);
      result.operator_products += more.operator_products;
      if (more.ok) pairs.next_value = more.values[wanted];
    }
    if (std::isnan(pairs.next_value)) {
      next_known = false;
      continue;
    }
    values_of[c].push_back(pairs.next_value);
    candidates.push_back({pairs.next_value, static_cast<std::int32_t>(c), wanted});
  }

  std::vector<std::int32_t> group;
  order_candidates(candidates, values_of, tie, group);
  result.values = Eigen::VectorXd::Zero(count);
  result.vectors = RowMatrixXd::Zero(n, count);
  result.components.resize(static_cast<std::size_t>(count));
  result.component_of_rows = components.labels;
  for (std::int32_t j = 0; j < count; ++j) {
    const Candidate& taken = candidates[static_cast<std::size_t>(j)];
    const LaplacianEigenpairs& pairs = solved[static_cast<std::size_t>(taken.component)];
    // A value-only candidate follows its component's `count` pairs: never taken.
    if (taken.index >= pairs.values.size()) {
      throw std::logic_error("smallest_laplacian_eigenpairs: a value-only candidate was taken");
    }
    result.values[j] = taken.value;
    result.components[static_cast<std::size_t>(j)] = taken.component;
    if (problems.empty()) {
      result.vectors.col(j) = pairs.vectors.col(taken.index);
    } else {
      const std::vector<std::int32_t>& rows =
          problems[static_cast<std::size_t>(taken.component)].rows;
      for (std::size_t r = 0; r < rows.size(); ++r) {
        result.vectors(rows[r], j) = pairs.vectors(static_cast<Eigen::Index>(r), taken.index);
      }
    }
  }
  const auto taken = static_cast<std::size_t>(count);
  result.next_value = next_known && candidates.size() > taken
                          ? candidates[taken].value
                          : std::numeric_limits<double>::quiet_NaN();
  result.degenerate =
      next_known && count > 0 && candidates.size() > taken && group[taken] == group[taken - 1];
  result.ok = true;
  normalize_eigenvector_signs(result.vectors);
  return result;
}

}  // namespace ggk::kernels
