#include "kernels/condition_estimate.hpp"

#include <cmath>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/LU>

namespace ggk::kernels {
namespace {

// dlacn2 with exact solves: on a diagonal matrix the estimate of ||A^-1||_1 is
// exact; on the n x n matrix with 1 on the diagonal and -1 above it (upper
// triangular, ||A^-1||_1 = 2^(n-1), the classic case of a hidden large inverse)
// it is found exactly too; never above the true norm.
TEST(ConditionEstimate, InverseOneNormOfKnownMatrices) {
  Eigen::MatrixXd diagonal = Eigen::MatrixXd::Zero(3, 3);
  diagonal.diagonal() << 2.0, 1e-3, 5.0;
  const auto solve_with = [](const Eigen::MatrixXd& a) {
    return [a](Eigen::VectorXd& v, bool transposed) {
      v = transposed ? Eigen::VectorXd(a.transpose().partialPivLu().solve(v))
                     : Eigen::VectorXd(a.partialPivLu().solve(v));
      return true;
    };
  };
  EXPECT_DOUBLE_EQ(inverse_one_norm_estimate(3, solve_with(diagonal)), 1e3);
  const int n = 20;
  Eigen::MatrixXd upper = Eigen::MatrixXd::Identity(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j) upper(i, j) = -1.0;
  const double exact = upper.inverse().cwiseAbs().colwise().sum().maxCoeff();
  EXPECT_EQ(exact, std::ldexp(1.0, n - 1));
  const double estimate = inverse_one_norm_estimate(n, solve_with(upper));
  EXPECT_LE(estimate, exact);
  EXPECT_GE(estimate, exact / 3.0);
  EXPECT_EQ(inverse_one_norm_estimate(0, solve_with(upper)), 0.0);
  EXPECT_EQ(inverse_one_norm_estimate(n, [](Eigen::VectorXd&, bool) { return false; }), 0.0);
}

TEST(ConditionEstimate, OneNormsAndTheReciprocal) {
  Eigen::MatrixXd a(3, 3);
  a << 1, -2, 0, 4, 1, 0, 0, 3, -1;
  EXPECT_EQ(one_norm(a.sparseView()), 6.0);  // column 1: 2 + 1 + 3
  // The symmetric matrix of a's lower triangle: columns 1 + 4, 4 + 1 + 3, 3 + 1.
  const SparseColMatrix lower = Eigen::MatrixXd(a.triangularView<Eigen::Lower>()).sparseView();
  EXPECT_EQ(symmetric_one_norm(lower), 8.0);
  EXPECT_EQ(symmetric_one_norm(a.sparseView()), 8.0);  // entries above the diagonal unread
  EXPECT_EQ(reciprocal_condition(4.0, 0.5), 0.5);
  EXPECT_EQ(reciprocal_condition(0.0, 0.5), 0.0);
  EXPECT_EQ(reciprocal_condition(4.0, INFINITY), 0.0);
}

}  // namespace
}  // namespace ggk::kernels
