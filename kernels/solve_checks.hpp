#pragma once
// The checks every LSPI solver makes around its factorisation, so that a sparse
// and a dense solve fail for the same reasons with the same messages
// (sparse_solvers.cpp, dense_solvers.cpp): the input's shape and finiteness
// before, the conditioning, the solution's finiteness and the residual after.
// Internal to kernels/.

#include <sstream>
#include <string>
#include <utility>

#include "kernels/eigen_types.hpp"
#include "kernels/sparse_solvers.hpp"

namespace ggk::kernels::solve_checks {

// False, with report.message set, when A (rows x cols) and b do not make a system.
inline bool shapes_match(Eigen::Index rows, Eigen::Index cols, const Eigen::VectorXd& b,
                         SolveReport& report) {
  if (rows == cols && rows == b.size()) return true;
  std::ostringstream message;
  message << "system shape mismatch: A is " << rows << " x " << cols << ", b has " << b.size()
          << " entries";
  report.message = message.str();
  return false;
}

// False, with report.message set, for a non-finite matrix entry or right-hand side.
inline bool finite_system(bool matrix_finite, const Eigen::VectorXd& b, SolveReport& report) {
  if (!matrix_finite) {
    report.message = "system matrix has non-finite entries";
    return false;
  }
  if (!b.allFinite()) {
    report.message = "right-hand side has non-finite entries";
    return false;
  }
  return true;
}

// After a successful factorisation: rejects a reciprocal condition estimate under
// min_rcond or a non-finite solution; otherwise records the relative residual
// ||apply(x) - b|| / ||b|| (apply(v) = A v), sets report.ok and moves the
// candidate into x. x is written only when every check passes.
template <class Apply>
void accept_solution(double rcond, double min_rcond, Eigen::VectorXd&& candidate,
                     const Eigen::VectorXd& b, const Apply& apply, SolveReport& report,
                     Eigen::VectorXd& x) {
  report.rcond = rcond;
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
  const Eigen::VectorXd residual = apply(candidate) - b;
  report.relative_residual = b_norm > 0.0 ? residual.norm() / b_norm : residual.norm();
  report.ok = true;
  x = std::move(candidate);
}

}  // namespace ggk::kernels::solve_checks
