#include "kernels/dense_solvers.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>

#include "kernels/blas_runtime.hpp"
#include "kernels/solve_checks.hpp"

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
  if (!solve_checks::shapes_match(a.rows(), a.cols(), b, report)) return false;
  if (a.rows() > std::numeric_limits<int>::max()) {
    report.message = "system too large for LAPACK's 32-bit indices";
    return false;
  }
  bool finite = true;  // over the part read, column by column (no copy)
  for (Eigen::Index col = 0; col < a.cols() && finite; ++col) {
    finite =
        part == Part::full ? a.col(col).allFinite() : a.col(col).tail(a.rows() - col).allFinite();
  }
  return solve_checks::finite_system(finite && std::isfinite(ridge), b, report);
}

// factor's lower triangle = that of A + ridge I (what dpotrf reads).
void load_lower(const Eigen::MatrixXd& a, double ridge, Eigen::MatrixXd& factor) {
  factor.resize(a.rows(), a.cols());
  factor.triangularView<Eigen::Lower>() = a.triangularView<Eigen::Lower>();
  factor.diagonal().array() += ridge;
}

}  // namespace

DenseSymmetricSolver::DenseSymmetricSolver(SolverSettings settings) : settings_(settings) {
  use_calling_thread_blas();
}

SolveReport DenseSymmetricSolver::solve(const Eigen::MatrixXd& a, double ridge,
                                        const Eigen::VectorXd& b, Eigen::VectorXd& x) {
  SolveReport report;
  if (!check_input(a, Part::lower, ridge, b, report)) return report;
  load_lower(a, ridge, factor_);
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
  solve_checks::accept_solution(
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

namespace {

// The strongly connected components of the block graph (block i -> block j when
// A_ij has a non-zero; every block depends on itself), by Tarjan's algorithm. A
// component is emitted after every component it depends on, which is the order of
// block forward substitution; blocks within a component in increasing order.
std::vector<std::vector<Eigen::Index>> block_components(
    const std::vector<std::vector<bool>>& depends) {
  const auto nb = static_cast<Eigen::Index>(depends.size());
  std::vector<Eigen::Index> index(static_cast<std::size_t>(nb), -1), low(index.size(), 0);
  std::vector<bool> on_stack(index.size(), false);
  std::vector<Eigen::Index> stack;
  std::vector<std::vector<Eigen::Index>> components;
  Eigen::Index counter = 0;
  // Recursion depth is at most the number of blocks (the actions: a handful).
  auto visit = [&](auto&& self, Eigen::Index v) -> void {
    const auto vi = static_cast<std::size_t>(v);
    index[vi] = low[vi] = counter++;
    stack.push_back(v);
    on_stack[vi] = true;
    for (Eigen::Index w = 0; w < nb; ++w) {
      const auto wi = static_cast<std::size_t>(w);
      if (w == v || !depends[vi][wi]) continue;
      if (index[wi] < 0) {
        self(self, w);
        low[vi] = std::min(low[vi], low[wi]);
      } else if (on_stack[wi]) {
        low[vi] = std::min(low[vi], index[wi]);
      }
    }
    if (low[vi] != index[vi]) return;
    std::vector<Eigen::Index> component;
    Eigen::Index w = -1;
    do {
      w = stack.back();
      stack.pop_back();
      on_stack[static_cast<std::size_t>(w)] = false;
      component.push_back(w);
    } while (w != v);
    std::sort(component.begin(), component.end());
    components.push_back(std::move(component));
  };
  for (Eigen::Index v = 0; v < nb; ++v) {
    if (index[static_cast<std::size_t>(v)] < 0) visit(visit, v);
  }
  return components;
}

}  // namespace

SolveReport DenseLuSolver::solve(const Eigen::MatrixXd& a, double ridge, const Eigen::VectorXd& b,
                                 Eigen::VectorXd& x, Eigen::Index block_size) {
  SolveReport report;
  if (!check_input(a, Part::full, ridge, b, report)) return report;
  const Eigen::Index n = a.rows();
  const Eigen::Index bs =
      block_size > 0 && n % block_size == 0 ? block_size : std::max<Eigen::Index>(n, 1);
  const Eigen::Index nb = n / bs;
  std::vector<std::vector<bool>> depends(static_cast<std::size_t>(nb),
                                         std::vector<bool>(static_cast<std::size_t>(nb), false));
  for (Eigen::Index i = 0; i < nb; ++i) {
    for (Eigen::Index j = 0; j < nb; ++j) {
      depends[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)] =
          i == j || (a.block(i * bs, j * bs, bs, bs).array() != 0.0).any();
    }
  }
  Eigen::VectorXd candidate = b;
  double min_pivot = std::numeric_limits<double>::infinity(), max_pivot = 0.0;
  for (const std::vector<Eigen::Index>& component : block_components(depends)) {
    // rhs_S = b_S - sum over solved blocks T of A_ST x_T (x_T in `candidate`);
    // a block that no solved block reaches keeps b_S bit for bit.
    const auto size = static_cast<Eigen::Index>(component.size()) * bs;
    Eigen::VectorXd rhs(size);
    factor_.resize(size, size);
    for (std::size_t r = 0; r < component.size(); ++r) {
      const Eigen::Index i = component[r];
      Eigen::Ref<Eigen::VectorXd> rhs_i = rhs.segment(static_cast<Eigen::Index>(r) * bs, bs);
      rhs_i = b.segment(i * bs, bs);
      for (Eigen::Index j = 0; j < nb; ++j) {
        const bool in_component = std::binary_search(component.begin(), component.end(), j);
        if (in_component || !depends[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)]) {
          continue;
        }
        rhs_i.noalias() -= a.block(i * bs, j * bs, bs, bs) * candidate.segment(j * bs, bs);
      }
      for (std::size_t c = 0; c < component.size(); ++c) {
        factor_.block(static_cast<Eigen::Index>(r) * bs, static_cast<Eigen::Index>(c) * bs, bs,
                      bs) = a.block(i * bs, component[c] * bs, bs, bs);
      }
    }
    factor_.diagonal().array() += ridge;
    const int m = static_cast<int>(size);
    const int lda = std::max(1, m);
    pivots_.resize(static_cast<std::size_t>(m));
    int info = 0;
    dgetrf_(&m, &m, factor_.data(), &lda, pivots_.data(), &info);
    if (info < 0) {
      report.message = "LAPACK dgetrf: argument " + std::to_string(-info) + " is invalid";
      return report;
    }
    if (info > 0) {
      const Eigen::Index column =
          component[static_cast<std::size_t>(info - 1) / static_cast<std::size_t>(bs)] * bs +
          (info - 1) % bs;
      report.message = "LAPACK dgetrf: matrix is singular (U(" + std::to_string(column) + ", " +
                       std::to_string(column) + ") is exactly zero)";
      return report;
    }
    const Eigen::VectorXd magnitudes = factor_.diagonal().cwiseAbs();
    min_pivot = std::min(min_pivot, magnitudes.minCoeff());
    max_pivot = std::max(max_pivot, magnitudes.maxCoeff());
    const int one = 1;
    dgetrs_("N", &m, &one, factor_.data(), &lda, pivots_.data(), rhs.data(), &lda, &info);
    for (std::size_t r = 0; r < component.size(); ++r) {
      candidate.segment(component[r] * bs, bs) = rhs.segment(static_cast<Eigen::Index>(r) * bs, bs);
    }
  }
  // UMFPACK_RCOND's estimate over the whole block triangular factor.
  const double rcond = n > 0 ? min_pivot / max_pivot : 0.0;
  solve_checks::accept_solution(
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
