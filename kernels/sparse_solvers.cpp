#include "kernels/sparse_solvers.hpp"

#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include <Eigen/CholmodSupport>
#include <Eigen/UmfPackSupport>

#include "kernels/blas_runtime.hpp"
#include "kernels/condition_estimate.hpp"
#include "kernels/solve_checks.hpp"

namespace ggk::kernels {

namespace {

// Eigen's wrappers keep the factor protected; these subclasses give both solvers
// one interface for solve_with(): analyse(A), factorise(A) -> failure message
// (empty on success), rcond(A): LAPACK's reciprocal 1-norm condition estimate
// (condition_estimate.hpp) from solves with the factor, apply(A, v) = A v.
class CholmodFactorization : public Eigen::CholmodDecomposition<SparseColMatrix, Eigen::Lower> {
 public:
  CholmodFactorization() {
    cholmod().print = 0;  // failures are reported, not printed
    // Always LL^T (supernodal or simplicial, CHOLMOD's choice): an LDL^T would
    // factor indefinite matrices without complaint, hiding a broken system.
    cholmod().supernodal = CHOLMOD_AUTO;
    cholmod().final_asis = 0;
    cholmod().final_ll = 1;
  }
  bool analyse(const SparseColMatrix& a) {
    analyzePattern(a);
    return true;
  }
  std::string factorise(const SparseColMatrix& a) {
    factorize(a);
    if (info() == Eigen::Success) return {};
    std::ostringstream message;
    message << "CHOLMOD: matrix is not positive definite (failed at column "
            << m_cholmodFactor->minor << " of " << a.rows() << ")";
    return message.str();
  }
  // A is symmetric: A^-T = A^-1.
  double rcond(const SparseColMatrix& a) {
    return reciprocal_condition(symmetric_one_norm(a),
                                inverse_one_norm_estimate(a.rows(), [&](Eigen::VectorXd& v, bool) {
                                  v = solve(v).eval();
                                  return info() == Eigen::Success;
                                }));
  }
  static Eigen::VectorXd apply(const SparseColMatrix& a, const Eigen::VectorXd& v) {
    return a.selfadjointView<Eigen::Lower>() * v;
  }
};

class UmfpackFactorization : public Eigen::UmfPackLU<SparseColMatrix> {
 public:
  bool analyse(const SparseColMatrix& a) {
    analyzePattern(a);
    return info() == Eigen::Success;
  }
  std::string factorise(const SparseColMatrix& a) {
    factorize(a);
    if (info() == Eigen::Success) return {};
    return "UMFPACK: matrix is singular (status " + std::to_string(umfpackFactorizeReturncode()) +
           ")";
  }
  double rcond(const SparseColMatrix& a) {
    return reciprocal_condition(
        one_norm(a), inverse_one_norm_estimate(a.rows(), [&](Eigen::VectorXd& v, bool transposed) {
          Eigen::VectorXd x(v.size());
          const auto status =
              Eigen::umfpack_solve(transposed ? UMFPACK_At : UMFPACK_A, mp_matrix.outerIndexPtr(),
                                   mp_matrix.innerIndexPtr(), mp_matrix.valuePtr(), x.data(),
                                   v.data(), m_numeric, m_control.data(), m_umfpackInfo.data());
          v = x;
          return status == UMFPACK_OK;
        }));
  }
  static Eigen::VectorXd apply(const SparseColMatrix& a, const Eigen::VectorXd& v) { return a * v; }
};

// The sparsity pattern of the last analysed matrix.
struct Pattern {
  Eigen::Index rows = -1;
  std::vector<std::int32_t> outer;
  std::vector<std::int32_t> inner;

  bool matches(const SparseColMatrix& a) const {
    if (a.rows() != rows || !a.isCompressed()) return false;
    const auto n_outer = static_cast<std::size_t>(a.outerSize()) + 1;
    const auto n_inner = static_cast<std::size_t>(a.nonZeros());
    return outer.size() == n_outer && inner.size() == n_inner &&
           std::equal(outer.begin(), outer.end(), a.outerIndexPtr()) &&
           std::equal(inner.begin(), inner.end(), a.innerIndexPtr());
  }
  void remember(const SparseColMatrix& a) {
    rows = a.rows();
    outer.assign(a.outerIndexPtr(), a.outerIndexPtr() + a.outerSize() + 1);
    inner.assign(a.innerIndexPtr(), a.innerIndexPtr() + a.nonZeros());
  }
};

bool check_input(const SparseColMatrix& a, const Eigen::VectorXd& b, SolveReport& report) {
  if (!solve_checks::shapes_match(a.rows(), a.cols(), b, report)) return false;
  bool finite = true;
  for (Eigen::Index k = 0; k < a.nonZeros() && finite; ++k) {
    finite = std::isfinite(a.valuePtr()[k]);
  }
  return solve_checks::finite_system(finite, b, report);
}

// The one solve path of both solvers: reuse the analysis while the pattern holds,
// factorise, then check conditioning, finiteness and the residual. x is written
// only when every check passes.
template <typename Factorization>
SolveReport solve_with(Factorization& factorization, Pattern& pattern, double min_rcond,
                       const SparseColMatrix& a, const Eigen::VectorXd& b, Eigen::VectorXd& x) {
  SolveReport report;
  if (!check_input(a, b, report)) return report;
  if (pattern.matches(a)) {
    report.reused_analysis = true;
  } else {
    if (!factorization.analyse(a)) {
      report.message = "symbolic analysis failed";
      pattern = Pattern{};
      return report;
    }
    pattern.remember(a);
  }
  report.message = factorization.factorise(a);
  if (!report.message.empty()) {
    pattern = Pattern{};  // the factor is unusable; analyse afresh next time
    return report;
  }
  solve_checks::accept_solution(
      factorization.rcond(a), min_rcond, factorization.solve(b), b,
      [&](const Eigen::VectorXd& v) { return Factorization::apply(a, v); }, report, x);
  return report;
}

}  // namespace

struct SymmetricSolver::Impl {
  SolverSettings settings;
  CholmodFactorization factorization;
  Pattern pattern;
};

SymmetricSolver::SymmetricSolver(SolverSettings settings) : impl_(std::make_unique<Impl>()) {
  use_calling_thread_blas();
  impl_->settings = settings;
}
SymmetricSolver::~SymmetricSolver() = default;
SymmetricSolver::SymmetricSolver(SymmetricSolver&&) noexcept = default;
SymmetricSolver& SymmetricSolver::operator=(SymmetricSolver&&) noexcept = default;

SolveReport SymmetricSolver::solve(const SparseColMatrix& a, const Eigen::VectorXd& b,
                                   Eigen::VectorXd& x) {
  return solve_with(impl_->factorization, impl_->pattern, impl_->settings.min_rcond, a, b, x);
}

struct NonsymmetricSolver::Impl {
  SolverSettings settings;
  UmfpackFactorization factorization;
  Pattern pattern;
};

NonsymmetricSolver::NonsymmetricSolver(SolverSettings settings) : impl_(std::make_unique<Impl>()) {
  use_calling_thread_blas();
  impl_->settings = settings;
}
NonsymmetricSolver::~NonsymmetricSolver() = default;
NonsymmetricSolver::NonsymmetricSolver(NonsymmetricSolver&&) noexcept = default;
NonsymmetricSolver& NonsymmetricSolver::operator=(NonsymmetricSolver&&) noexcept = default;

SolveReport NonsymmetricSolver::solve(const SparseColMatrix& a, const Eigen::VectorXd& b,
                                      Eigen::VectorXd& x) {
  return solve_with(impl_->factorization, impl_->pattern, impl_->settings.min_rcond, a, b, x);
}

}  // namespace ggk::kernels
