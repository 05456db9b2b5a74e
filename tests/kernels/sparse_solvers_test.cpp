#include "kernels/sparse_solvers.hpp"

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "kernels/random_stream.hpp"

namespace ggk::kernels {
namespace {

SparseColMatrix random_sparse_spd(int n, std::uint64_t seed) {
  RandomStream rng(seed, 0, 0);
  Eigen::MatrixXd m(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) m(i, j) = rng.uniform() < 0.3 ? rng.uniform(-1, 1) : 0.0;
  Eigen::MatrixXd a = m.transpose() * m + Eigen::MatrixXd::Identity(n, n);
  return a.sparseView();
}

TEST(SymmetricSolver, SolvesPositiveDefiniteSystems) {
  const SparseColMatrix a = random_sparse_spd(30, 1);
  const Eigen::VectorXd expected = Eigen::VectorXd::LinSpaced(30, -1, 2);
  const Eigen::VectorXd b = a * expected;
  SymmetricSolver solver;
  Eigen::VectorXd x;
  const SolveReport report = solver.solve(a, b, x);
  ASSERT_TRUE(report.ok) << report.message;
  EXPECT_LT((x - expected).norm(), 1e-10);
  EXPECT_LT(report.relative_residual, 1e-12);
  EXPECT_GT(report.rcond, 0.0);
  EXPECT_FALSE(report.reused_analysis);
}

TEST(SymmetricSolver, ReusesAnalysisWhilePatternHolds) {
  const SparseColMatrix a = random_sparse_spd(20, 2);
  const SparseColMatrix a2 = 2.0 * a;
  const Eigen::VectorXd b = Eigen::VectorXd::Ones(20);
  SymmetricSolver solver;
  Eigen::VectorXd x1, x2;
  EXPECT_FALSE(solver.solve(a, b, x1).reused_analysis);
  const SolveReport second = solver.solve(a2, b, x2);
  EXPECT_TRUE(second.reused_analysis);
  EXPECT_LT((2.0 * x2 - x1).norm(), 1e-10);
  const SparseColMatrix other = random_sparse_spd(20, 3);
  EXPECT_FALSE(solver.solve(other, b, x2).reused_analysis);
}

TEST(SymmetricSolver, ReportsIndefiniteSingularAndNonFiniteSystems) {
  SymmetricSolver solver;
  Eigen::VectorXd x = Eigen::VectorXd::Constant(2, 7.0);
  const Eigen::VectorXd b = Eigen::VectorXd::Ones(2);

  Eigen::MatrixXd indefinite(2, 2);
  indefinite << 1, 0, 0, -1;
  SolveReport report = solver.solve(SparseColMatrix(indefinite.sparseView()), b, x);
  EXPECT_FALSE(report.ok);
  EXPECT_NE(report.message.find("not positive definite"), std::string::npos) << report.message;

  Eigen::MatrixXd nearly_singular(2, 2);
  nearly_singular << 1, 0, 0, 1e-20;
  report = solver.solve(SparseColMatrix(nearly_singular.sparseView()), b, x);
  EXPECT_FALSE(report.ok);
  EXPECT_NE(report.message.find("ill-conditioned"), std::string::npos) << report.message;

  Eigen::MatrixXd with_nan(2, 2);
  with_nan << 1, 0, 0, std::numeric_limits<double>::quiet_NaN();
  report = solver.solve(SparseColMatrix(with_nan.sparseView()), b, x);
  EXPECT_FALSE(report.ok);

  // The output is untouched on failure.
  EXPECT_EQ(x, Eigen::VectorXd::Constant(2, 7.0));
}

TEST(NonsymmetricSolver, SolvesGeneralSystems) {
  RandomStream rng(4, 0, 0);
  Eigen::MatrixXd dense = Eigen::MatrixXd::Identity(25, 25) * 3.0;
  for (int i = 0; i < 25; ++i)
    for (int j = 0; j < 25; ++j)
      if (rng.uniform() < 0.2) dense(i, j) += rng.uniform(-1, 1);
  const SparseColMatrix a = dense.sparseView();
  const Eigen::VectorXd expected = Eigen::VectorXd::LinSpaced(25, 1, 3);
  NonsymmetricSolver solver;
  Eigen::VectorXd x;
  const SolveReport report = solver.solve(a, a * expected, x);
  ASSERT_TRUE(report.ok) << report.message;
  EXPECT_LT((x - expected).norm(), 1e-10);
  EXPECT_TRUE(solver.solve(a, a * expected, x).reused_analysis);
}

TEST(NonsymmetricSolver, ReportsSingularSystems) {
  Eigen::MatrixXd singular(3, 3);
  singular << 1, 2, 3, 2, 4, 6, 0, 1, 1;
  NonsymmetricSolver solver;
  Eigen::VectorXd x;
  const SolveReport report =
      solver.solve(SparseColMatrix(singular.sparseView()), Eigen::VectorXd::Ones(3), x);
  EXPECT_FALSE(report.ok);
  EXPECT_FALSE(report.message.empty());
  EXPECT_EQ(x.size(), 0);
}

}  // namespace
}  // namespace ggk::kernels
