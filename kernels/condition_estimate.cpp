#include "kernels/condition_estimate.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

extern "C" {
// LAPACK's reverse-communication 1-norm estimator (32-bit integers, as Debian
// builds LAPACK and OpenBLAS).
void dlacn2_(const int* n, double* v, double* x, int* isgn, double* est, int* kase, int* isave);
}

namespace ggk::kernels {

double inverse_one_norm_estimate(Eigen::Index n, const FactorSolve& solve) {
  if (n <= 0 || n > std::numeric_limits<int>::max()) return 0.0;
  const int order = static_cast<int>(n);
  Eigen::VectorXd v(n), x(n);
  std::vector<int> isgn(static_cast<std::size_t>(n));
  int isave[3] = {0, 0, 0};
  double estimate = 0.0;
  int kase = 0;
  // dlacn2 asks for A^-1 x (kase 1) or A^-T x (kase 2) until it returns kase 0;
  // it starts from x = (1/n, ..., 1/n) and takes at most five steps.
  for (;;) {
    dlacn2_(&order, v.data(), x.data(), isgn.data(), &estimate, &kase, isave);
    if (kase == 0) break;
    if (!solve(x, kase == 2) || !x.allFinite()) return 0.0;
  }
  return estimate;
}

double reciprocal_condition(double a_one_norm, double inverse_one_norm) {
  const double product = a_one_norm * inverse_one_norm;
  if (!(product > 0.0) || !std::isfinite(product)) return 0.0;
  return 1.0 / product;
}

double one_norm(const SparseColMatrix& a) {
  double largest = 0.0;
  for (Eigen::Index col = 0; col < a.outerSize(); ++col) {
    double sum = 0.0;
    for (SparseColMatrix::InnerIterator it(a, col); it; ++it) sum += std::abs(it.value());
    largest = std::max(largest, sum);
  }
  return largest;
}

double symmetric_one_norm(const SparseColMatrix& lower) {
  // Column j of the whole matrix: column j of the lower triangle and, mirrored,
  // row j's entries left of the diagonal.
  Eigen::VectorXd sums = Eigen::VectorXd::Zero(lower.cols());
  for (Eigen::Index col = 0; col < lower.outerSize(); ++col) {
    for (SparseColMatrix::InnerIterator it(lower, col); it; ++it) {
      if (it.row() < col) continue;  // not in the lower triangle: not read
      sums(col) += std::abs(it.value());
      if (it.row() != col) sums(it.row()) += std::abs(it.value());
    }
  }
  return sums.size() > 0 ? sums.maxCoeff() : 0.0;
}

}  // namespace ggk::kernels
