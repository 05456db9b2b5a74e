#include "kernels/sparse_solvers.hpp"

#include <cmath>
#include <sstream>
#include <vector>

#include <Eigen/CholmodSupport>
#include <Eigen/UmfPackSupport>

namespace ggk::kernels {

namespace {

// Eigen's wrappers keep the factor and the solver's info array protected; these
// subclasses expose the reciprocal condition estimates and nothing else.
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
  double rcond() { return cholmod_rcond(m_cholmodFactor, &cholmod()); }
  std::int64_t failed_column() const { return static_cast<std::int64_t>(m_cholmodFactor->minor); }
};

class UmfpackFactorization : public Eigen::UmfPackLU<SparseColMatrix> {
 public:
  double rcond() const { return m_umfpackInfo(UMFPACK_RCOND); }
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
  if (a.rows() != a.cols() || a.rows() != b.size()) {
    std::ostringstream message;
    message << "system shape mismatch: A is " << a.rows() << " x " << a.cols() << ", b has "
            << b.size() << " entries";
    report.message = message.str();
    return false;
  }
  for (Eigen::Index k = 0; k < a.nonZeros(); ++k) {
    if (!std::isfinite(a.valuePtr()[k])) {
      report.message = "system matrix has non-finite entries";
      return false;
    }
  }
  if (!b.allFinite()) {
    report.message = "right-hand side has non-finite entries";
    return false;
  }
  return true;
}

// Shared tail of both solvers: conditioning, finiteness and residual checks.
template <typename Apply>
void check_solution(double min_rcond, const Eigen::VectorXd& b, const Eigen::VectorXd& candidate,
                    Apply apply_a, SolveReport& report, Eigen::VectorXd& x) {
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
  const Eigen::VectorXd residual = apply_a(candidate) - b;
  report.relative_residual = b_norm > 0.0 ? residual.norm() / b_norm : residual.norm();
  report.ok = true;
  x = candidate;
}

}  // namespace

struct SymmetricSolver::Impl {
  SolverSettings settings;
  CholmodFactorization factorization;
  Pattern pattern;
};

SymmetricSolver::SymmetricSolver(SolverSettings settings) : impl_(std::make_unique<Impl>()) {
  impl_->settings = settings;
}
SymmetricSolver::~SymmetricSolver() = default;
SymmetricSolver::SymmetricSolver(SymmetricSolver&&) noexcept = default;
SymmetricSolver& SymmetricSolver::operator=(SymmetricSolver&&) noexcept = default;

SolveReport SymmetricSolver::solve(const SparseColMatrix& a, const Eigen::VectorXd& b,
                                   Eigen::VectorXd& x) {
  SolveReport report;
  if (!check_input(a, b, report)) return report;
  if (impl_->pattern.matches(a)) {
    report.reused_analysis = true;
  } else {
    impl_->factorization.analyzePattern(a);
    impl_->pattern.remember(a);
  }
  impl_->factorization.factorize(a);
  if (impl_->factorization.info() != Eigen::Success) {
    std::ostringstream message;
    message << "CHOLMOD: matrix is not positive definite (failed at column "
            << impl_->factorization.failed_column() << " of " << a.rows() << ")";
    report.message = message.str();
    // The factor is unusable; analyse afresh next time.
    impl_->pattern = Pattern{};
    return report;
  }
  report.rcond = impl_->factorization.rcond();
  const Eigen::VectorXd candidate = impl_->factorization.solve(b);
  check_solution(
      impl_->settings.min_rcond, b, candidate,
      [&](const Eigen::VectorXd& v) -> Eigen::VectorXd {
        return a.selfadjointView<Eigen::Lower>() * v;
      },
      report, x);
  return report;
}

struct NonsymmetricSolver::Impl {
  SolverSettings settings;
  UmfpackFactorization factorization;
  Pattern pattern;
};

NonsymmetricSolver::NonsymmetricSolver(SolverSettings settings) : impl_(std::make_unique<Impl>()) {
  impl_->settings = settings;
}
NonsymmetricSolver::~NonsymmetricSolver() = default;
NonsymmetricSolver::NonsymmetricSolver(NonsymmetricSolver&&) noexcept = default;
NonsymmetricSolver& NonsymmetricSolver::operator=(NonsymmetricSolver&&) noexcept = default;

SolveReport NonsymmetricSolver::solve(const SparseColMatrix& a, const Eigen::VectorXd& b,
                                      Eigen::VectorXd& x) {
  SolveReport report;
  if (!check_input(a, b, report)) return report;
  if (impl_->pattern.matches(a)) {
    report.reused_analysis = true;
  } else {
    impl_->factorization.analyzePattern(a);
    if (impl_->factorization.info() != Eigen::Success) {
      report.message = "UMFPACK: symbolic analysis failed";
      impl_->pattern = Pattern{};
      return report;
    }
    impl_->pattern.remember(a);
  }
  impl_->factorization.factorize(a);
  report.rcond = impl_->factorization.rcond();
  if (impl_->factorization.info() != Eigen::Success) {
    std::ostringstream message;
    message << "UMFPACK: matrix is singular (status "
            << impl_->factorization.umfpackFactorizeReturncode() << ")";
    report.message = message.str();
    impl_->pattern = Pattern{};
    return report;
  }
  const Eigen::VectorXd candidate = impl_->factorization.solve(b);
  check_solution(
      impl_->settings.min_rcond, b, candidate,
      [&](const Eigen::VectorXd& v) -> Eigen::VectorXd { return a * v; }, report, x);
  return report;
}

}  // namespace ggk::kernels
