#include "kernels/dense_solvers.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>

#include "kernels/blas_runtime.hpp"
#include "kernels/condition_estimate.hpp"
#include "kernels/flop_count.hpp"
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
double dlansy_(const char* norm, const char* uplo, const int* n, const double* a, const int* lda,
               double* work);
void dpocon_(const char* uplo, const int* n, const double* a, const int* lda, const double* anorm,
             double* rcond, double* work, int* iwork, int* info);
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
  work_.resize(3 * static_cast<Eigen::Index>(n));
  iwork_.resize(static_cast<std::size_t>(n));
  const double a_norm =
      dlansy_("1", "L", &n, factor_.data(), &lda, work_.data());  // ||A + ridge I||_1
  int info = 0;
  dpotrf_("L", &n, factor_.data(), &lda, &info);
  count_flops(static_cast<double>(n) * n * n / 3.0);
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
  // LAPACK's 1-norm estimate on the factor (condition_estimate.hpp says what it is).
  double rcond = 0.0;
  if (n > 0) {
    dpocon_("L", &n, factor_.data(), &lda, &a_norm, &rcond, work_.data(), iwork_.data(), &info);
    if (info != 0) rcond = 0.0;
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

// v <- (A + ridge I)^-1 v, or its transpose's, with the components' factors: A is
// block lower triangular in component order, A^T block upper triangular, solved
// from the last component back.
bool DenseLuSolver::block_solve(const Eigen::MatrixXd& a, Eigen::Index bs,
                                const std::vector<std::vector<bool>>& depends,
                                const std::vector<std::vector<Eigen::Index>>& components,
                                Eigen::VectorXd& v, bool transposed) const {
  const auto count = static_cast<std::ptrdiff_t>(components.size());
  const Eigen::Index nb = static_cast<Eigen::Index>(depends.size());
  std::vector<bool> solved(static_cast<std::size_t>(nb), false);
  for (std::ptrdiff_t step = 0; step < count; ++step) {
    const auto k = static_cast<std::size_t>(transposed ? count - 1 - step : step);
    const std::vector<Eigen::Index>& component = components[k];
    const auto size = static_cast<Eigen::Index>(component.size()) * bs;
    Eigen::VectorXd rhs(size);
    for (std::size_t r = 0; r < component.size(); ++r) {
      const Eigen::Index i = component[r];
      Eigen::Ref<Eigen::VectorXd> rhs_i = rhs.segment(static_cast<Eigen::Index>(r) * bs, bs);
      rhs_i = v.segment(i * bs, bs);
      for (Eigen::Index j = 0; j < nb; ++j) {
        if (!solved[static_cast<std::size_t>(j)]) continue;
        // A_ij x_j (A x = v), or A_ji^T x_j (A^T x = v): the off-diagonal blocks
        // hold no ridge.
        if (!transposed && depends[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)]) {
          rhs_i.noalias() -= a.block(i * bs, j * bs, bs, bs) * v.segment(j * bs, bs);
        } else if (transposed &&
                   depends[static_cast<std::size_t>(j)][static_cast<std::size_t>(i)]) {
          rhs_i.noalias() -= a.block(j * bs, i * bs, bs, bs).transpose() * v.segment(j * bs, bs);
        }
      }
    }
    const int m = static_cast<int>(size);
    const int lda = std::max(1, m);
    const int one = 1;
    int info = 0;
    dgetrs_(transposed ? "T" : "N", &m, &one, factors_[k].data(), &lda, pivots_[k].data(),
            rhs.data(), &lda, &info);
    if (info != 0) return false;
    for (std::size_t r = 0; r < component.size(); ++r) {
      v.segment(component[r] * bs, bs) = rhs.segment(static_cast<Eigen::Index>(r) * bs, bs);
      solved[static_cast<std::size_t>(component[r])] = true;
    }
  }
  return true;
}

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
  const std::vector<std::vector<Eigen::Index>> components = block_components(depends);
  if (factors_.size() < components.size()) factors_.resize(components.size());
  if (pivots_.size() < components.size()) pivots_.resize(components.size());
  for (std::size_t k = 0; k < components.size(); ++k) {
    const std::vector<Eigen::Index>& component = components[k];
    Eigen::MatrixXd& factor = factors_[k];
    std::vector<int>& component_pivots = pivots_[k];
    // rhs_S = b_S - sum over solved blocks T of A_ST x_T (x_T in `candidate`);
    // a block that no solved block reaches keeps b_S bit for bit.
    const auto size = static_cast<Eigen::Index>(component.size()) * bs;
    Eigen::VectorXd rhs(size);
    factor.resize(size, size);
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
        factor.block(static_cast<Eigen::Index>(r) * bs, static_cast<Eigen::Index>(c) * bs, bs, bs) =
            a.block(i * bs, component[c] * bs, bs, bs);
      }
    }
    factor.diagonal().array() += ridge;
    const int m = static_cast<int>(size);
    const int lda = std::max(1, m);
    component_pivots.resize(static_cast<std::size_t>(m));
    int info = 0;
    dgetrf_(&m, &m, factor.data(), &lda, component_pivots.data(), &info);
    count_flops(2.0 * m * m * m / 3.0);
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
    const int one = 1;
    dgetrs_("N", &m, &one, factor.data(), &lda, component_pivots.data(), rhs.data(), &lda, &info);
    for (std::size_t r = 0; r < component.size(); ++r) {
      candidate.segment(component[r] * bs, bs) = rhs.segment(static_cast<Eigen::Index>(r) * bs, bs);
    }
  }
  // LAPACK's 1-norm estimate (dgecon's, condition_estimate.hpp) over the whole
  // block triangular factor: ||A + ridge I||_1, and dlacn2 with its solves.
  double a_norm = 0.0;
  for (Eigen::Index col = 0; col < n; ++col) {
    a_norm = std::max(a_norm, a.col(col).cwiseAbs().sum() - std::abs(a(col, col)) +
                                  std::abs(a(col, col) + ridge));
  }
  const double rcond = reciprocal_condition(
      a_norm, inverse_one_norm_estimate(n, [&](Eigen::VectorXd& v, bool transposed) {
        return block_solve(a, bs, depends, components, v, transposed);
      }));
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
