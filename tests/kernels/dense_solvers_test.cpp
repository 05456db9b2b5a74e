#include "kernels/dense_solvers.hpp"

#include <atomic>
#include <cmath>
#include <cstdint>
#include <limits>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/QR>

#include "kernels/random_stream.hpp"
#include "kernels/sparse_solvers.hpp"

namespace ggk::kernels {
namespace {

Eigen::MatrixXd random_spd(int n, std::uint64_t seed) {
  RandomStream rng(seed, 0, 0);
  Eigen::MatrixXd m(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) m(i, j) = rng.uniform(-1, 1);
  return m.transpose() * m + Eigen::MatrixXd::Identity(n, n);
}

TEST(DenseSymmetricSolver, SolvesPositiveDefiniteSystemsWithTheRidgeOnTheDiagonal) {
  const Eigen::MatrixXd a = random_spd(40, 1);
  const Eigen::VectorXd expected = Eigen::VectorXd::LinSpaced(40, -1, 2);
  const double ridge = 0.5;
  const Eigen::VectorXd b = a * expected + ridge * expected;
  // Only the lower triangle is read: garbage above the diagonal changes nothing.
  Eigen::MatrixXd lower_only = a;
  lower_only.triangularView<Eigen::StrictlyUpper>().setConstant(1e30);
  DenseSymmetricSolver solver;
  Eigen::VectorXd x;
  const SolveReport report = solver.solve(lower_only, ridge, b, x);
  ASSERT_TRUE(report.ok) << report.message;
  EXPECT_LT((x - expected).norm(), 1e-10);
  EXPECT_LT(report.relative_residual, 1e-13);
  EXPECT_FALSE(report.reused_analysis);
}

// Q diag(d) R^T with Q, R orthogonal (R = Q when symmetric: positive definite) and
// d from 1 down to 1 / condition, evenly in log: its 2-norm condition number is
// `condition`, and no diagonal of a factor shows it.
Eigen::MatrixXd known_condition(int n, double condition, bool symmetric, std::uint64_t seed) {
  RandomStream rng(seed, 0, 0);
  auto orthogonal = [&] {
    Eigen::MatrixXd m(n, n);
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) m(i, j) = rng.uniform(-1, 1);
    return Eigen::MatrixXd(Eigen::HouseholderQR<Eigen::MatrixXd>(m).householderQ());
  };
  const Eigen::MatrixXd q = orthogonal();
  const Eigen::MatrixXd r = symmetric ? q : orthogonal();
  Eigen::VectorXd d(n);
  for (int i = 0; i < n; ++i) d(i) = std::pow(condition, -static_cast<double>(i) / (n - 1));
  Eigen::MatrixXd a = q * d.asDiagonal() * r.transpose();
  if (symmetric) a = (0.5 * (a + a.transpose())).eval();
  return a;
}

// 1 / (||A||_1 ||A^-1||_1), from the inverse.
double exact_rcond_one_norm(const Eigen::MatrixXd& a) {
  return 1.0 / (a.cwiseAbs().colwise().sum().maxCoeff() *
                a.inverse().cwiseAbs().colwise().sum().maxCoeff());
}

// Every solver, dense and sparse, reports LAPACK's 1-norm estimate: never below the
// true reciprocal 1-norm condition (the estimate of ||A^-1||_1 is a lower bound)
// and within a factor of 3 of it, on matrices of 2-norm condition 1e4 .. 1e11.
// The estimates of diagonals of the factors ((min L_ii / max L_ii)^2, min |U_ii| /
// max |U_ii|) were up to 1e4 times too optimistic on such matrices.
TEST(ConditionEstimate, EverySolverEstimatesTheOneNormConditionOfAKnownMatrix) {
  const int n = 40;
  for (const double condition : {1e4, 1e8, 1e11}) {
    const Eigen::MatrixXd spd = known_condition(n, condition, true, 11);
    const Eigen::MatrixXd general = known_condition(n, condition, false, 12);
    // Block lower triangular (blocks of n/2, two components): the estimate runs
    // over the whole block triangular factor, transposed solves included.
    Eigen::MatrixXd blocked = Eigen::MatrixXd::Zero(n, n);
    blocked.topLeftCorner(n / 2, n / 2) = known_condition(n / 2, condition, false, 13);
    blocked.bottomRightCorner(n / 2, n / 2) = known_condition(n / 2, 10.0, false, 14);
    blocked.bottomLeftCorner(n / 2, n / 2) = known_condition(n / 2, 10.0, false, 15);
    const Eigen::VectorXd b = Eigen::VectorXd::Ones(n);
    auto expect_estimate = [&](const SolveReport& report, const Eigen::MatrixXd& a,
                               const char* solver) {
      ASSERT_TRUE(report.ok) << solver << ": " << report.message;
      const double exact = exact_rcond_one_norm(a);
      EXPECT_GE(report.rcond, exact * (1 - 1e-3)) << solver << ", condition " << condition;
      EXPECT_LE(report.rcond, 3.0 * exact) << solver << ", condition " << condition;
      // The 1-norm and 2-norm conditions differ by at most a factor n.
      EXPECT_GE(report.rcond * condition, 1.0 / n) << solver;
      EXPECT_LE(report.rcond * condition, 3.0 * n) << solver;
    };
    Eigen::VectorXd x;
    DenseSymmetricSolver dense_symmetric;
    expect_estimate(dense_symmetric.solve(spd, 0.0, b, x), spd, "dpotrf");
    SymmetricSolver sparse_symmetric;
    const SparseColMatrix lower = Eigen::MatrixXd(spd.triangularView<Eigen::Lower>()).sparseView();
    expect_estimate(sparse_symmetric.solve(lower, b, x), spd, "CHOLMOD");
    DenseLuSolver dense_lu;
    expect_estimate(dense_lu.solve(general, 0.0, b, x), general, "dgetrf");
    expect_estimate(dense_lu.solve(blocked, 0.0, b, x, n / 2), blocked, "dgetrf, blocks");
    NonsymmetricSolver sparse_lu;
    expect_estimate(sparse_lu.solve(general.sparseView(), b, x), general, "UMFPACK");
    expect_estimate(sparse_lu.solve(blocked.sparseView(), b, x), blocked, "UMFPACK, blocks");
  }
}

// With a ridge: the estimate is of A + ridge I. diag(4, 1e-4) + 1e-4 I: exactly
// 2e-4 / 4.0001.
TEST(ConditionEstimate, IsOfTheSystemWithItsRidge) {
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(2, 2);
  a(0, 0) = 4.0;
  a(1, 1) = 1e-4;
  Eigen::VectorXd x;
  DenseSymmetricSolver solver;
  EXPECT_DOUBLE_EQ(solver.solve(a, 1e-4, Eigen::VectorXd::Ones(2), x).rcond, 2e-4 / 4.0001);
  DenseLuSolver lu;
  EXPECT_DOUBLE_EQ(lu.solve(a, 1e-4, Eigen::VectorXd::Ones(2), x).rcond, 2e-4 / 4.0001);
  SymmetricSolver sparse;
  EXPECT_DOUBLE_EQ(sparse.solve(a.sparseView(), Eigen::VectorXd::Ones(2), x).rcond, 2.5e-5);
}

TEST(DenseSymmetricSolver, ReportsIndefiniteIllConditionedAndNonFiniteSystems) {
  DenseSymmetricSolver solver;
  Eigen::VectorXd x = Eigen::VectorXd::Constant(2, 7.0);
  const Eigen::VectorXd b = Eigen::VectorXd::Ones(2);

  Eigen::MatrixXd indefinite(2, 2);
  indefinite << 1, 0, 0, -1;
  SolveReport report = solver.solve(indefinite, 0.0, b, x);
  EXPECT_FALSE(report.ok);
  EXPECT_NE(report.message.find("not positive definite (failed at column 1 of 2)"),
            std::string::npos)
      << report.message;

  Eigen::MatrixXd nearly_singular(2, 2);
  nearly_singular << 1, 0, 0, 1e-20;
  report = solver.solve(nearly_singular, 0.0, b, x);
  EXPECT_FALSE(report.ok);
  EXPECT_NE(report.message.find("ill-conditioned"), std::string::npos) << report.message;

  Eigen::MatrixXd with_nan(2, 2);
  with_nan << 1, 0, std::numeric_limits<double>::quiet_NaN(), 1;
  report = solver.solve(with_nan, 0.0, b, x);
  EXPECT_FALSE(report.ok);
  EXPECT_NE(report.message.find("non-finite"), std::string::npos) << report.message;

  report = solver.solve(Eigen::MatrixXd::Identity(2, 2), 0.0, Eigen::VectorXd::Ones(3), x);
  EXPECT_FALSE(report.ok);
  EXPECT_NE(report.message.find("shape mismatch"), std::string::npos) << report.message;

  // The output is untouched on failure.
  EXPECT_EQ(x, Eigen::VectorXd::Constant(2, 7.0));
}

// The condition estimates do not depend on where the heap puts the solver's
// buffers: OpenBLAS's dot products in dpocon's triangular solves sum in an order
// that depends on a vector's offset within a cache line, and with the heap's
// 16-byte alignment the estimate of this 280 x 280 system (a Khepera fit's order
// at 70 kernels) moved in its last bit with the allocations made before the
// solver's (kernels/CMakeLists.txt: EIGEN_MAX_ALIGN_BYTES). Every dynamic Eigen
// object starts on a cache line.
TEST(DenseSymmetricSolver, ConditionEstimatesDoNotDependOnTheHeapLayout) {
  const Eigen::MatrixXd a = random_spd(280, 3);
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(280, -1, 1);
  const Eigen::MatrixXd lu_a = a + Eigen::MatrixXd::Identity(280, 280) * 0.25;
  double symmetric_rcond = -1.0, lu_rcond = -1.0;
  for (int shift = 0; shift < 8; ++shift) {
    // Allocations of 16-byte steps before the solvers' own.
    std::vector<std::vector<double>> padding;
    for (int k = 0; k <= shift; ++k) padding.emplace_back(static_cast<std::size_t>(2 * k + 1));
    DenseSymmetricSolver symmetric;
    DenseLuSolver lu;
    Eigen::VectorXd x, y;
    const SolveReport symmetric_report = symmetric.solve(a, 1e-6, b, x);
    const SolveReport lu_report = lu.solve(lu_a, 1e-6, b, y);
    ASSERT_TRUE(symmetric_report.ok && lu_report.ok);
    EXPECT_EQ(reinterpret_cast<std::uintptr_t>(x.data()) % 64, 0u);
    if (shift == 0) {
      symmetric_rcond = symmetric_report.rcond;
      lu_rcond = lu_report.rcond;
    }
    EXPECT_EQ(symmetric_report.rcond, symmetric_rcond) << "shift " << shift;
    EXPECT_EQ(lu_report.rcond, lu_rcond) << "shift " << shift;
  }
}

TEST(DenseLuSolver, SolvesGeneralSystems) {
  RandomStream rng(4, 0, 0);
  Eigen::MatrixXd a = Eigen::MatrixXd::Identity(25, 25) * 3.0;
  for (int i = 0; i < 25; ++i)
    for (int j = 0; j < 25; ++j) a(i, j) += rng.uniform(-1, 1);
  const Eigen::VectorXd expected = Eigen::VectorXd::LinSpaced(25, 1, 3);
  DenseLuSolver solver;
  Eigen::VectorXd x;
  const SolveReport report = solver.solve(a, 1e-3, a * expected + 1e-3 * expected, x);
  ASSERT_TRUE(report.ok) << report.message;
  EXPECT_LT((x - expected).norm(), 1e-10);
  EXPECT_GT(report.rcond, 0.0);
  EXPECT_LE(report.rcond, 1.0);
}

TEST(DenseLuSolver, ReportsSingularSystemsAndLeavesTheOutputAlone) {
  Eigen::MatrixXd singular(3, 3);
  singular << 1, 2, 3, 2, 4, 6, 0, 1, 1;
  DenseLuSolver solver;
  Eigen::VectorXd x;
  const SolveReport report = solver.solve(singular, 0.0, Eigen::VectorXd::Ones(3), x);
  EXPECT_FALSE(report.ok);
  EXPECT_FALSE(report.message.empty());
  EXPECT_EQ(x.size(), 0);
}

// Blocks of 3: x0 = A00^-1 b0 with b0 = 0, so x0 is zero in exact arithmetic;
// the rows of block 1 have larger entries in block 0's columns, so a pivoted LU
// of the whole matrix takes its pivots there and mixes b1 into x0's elimination.
// The block triangular form solves block 0 alone: exact zeros.
TEST(DenseLuSolver, BlockTriangularFormKeepsExactZeros) {
  RandomStream rng(8, 0, 0);
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(6, 6);
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      a(i, j) = (i == j ? 1.0 : 0.0) + 0.1 * rng.uniform(-1, 1);
      a(3 + i, j) = 10.0 + rng.uniform(-1, 1);  // block (1, 0), large
      a(3 + i, 3 + j) = (i == j ? 2.0 : 0.0) + 0.1 * rng.uniform(-1, 1);
    }
  }
  Eigen::VectorXd b(6);
  b << 0, 0, 0, 1.0 / 3.0, 0.7, -2.0 / 7.0;
  DenseLuSolver solver;
  Eigen::VectorXd blocked, whole;
  ASSERT_TRUE(solver.solve(a, 0.0, b, blocked, 3).ok);
  EXPECT_TRUE((blocked.head(3).array() == 0.0).all()) << blocked.transpose();
  ASSERT_TRUE(solver.solve(a, 0.0, b, whole).ok);
  EXPECT_LT((whole - blocked).norm(), 1e-12);
  // Block 1 alone: x1 = A11^-1 b1.
  const Eigen::VectorXd x1 = a.block(3, 3, 3, 3).partialPivLu().solve(b.tail(3));
  EXPECT_LT((blocked.tail(3) - x1).norm(), 1e-14);
}

TEST(DenseLuSolver, BlockTriangularFormOfAnIrreducibleMatrixIsThePlainLu) {
  RandomStream rng(9, 0, 0);
  Eigen::MatrixXd a = Eigen::MatrixXd::Identity(8, 8) * 3.0;
  for (int i = 0; i < 8; ++i)
    for (int j = 0; j < 8; ++j) a(i, j) += rng.uniform(-1, 1);
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(8, -1, 1);
  DenseLuSolver solver;
  Eigen::VectorXd blocked, whole;
  const SolveReport blocked_report = solver.solve(a, 0.5, b, blocked, 4);
  const SolveReport whole_report = solver.solve(a, 0.5, b, whole);
  ASSERT_TRUE(blocked_report.ok && whole_report.ok);
  EXPECT_EQ(blocked, whole);  // the same bits
  EXPECT_EQ(blocked_report.rcond, whole_report.rcond);
}

// LAPACK's factorisations from four threads at once (as LSPI fits in TBB tasks
// call them) equal the same solves on one thread, bit for bit.
TEST(DenseSolvers, ConcurrentSolvesEqualSequentialOnesBitForBit) {
  struct Case {
    Eigen::MatrixXd a;
    Eigen::VectorXd b, cholesky, lu;
  };
  std::vector<Case> cases;
  for (int c = 0; c < 12; ++c) {
    const int n = 20 + 37 * c;
    Case item{random_spd(n, 100 + static_cast<std::uint64_t>(c)),
              Eigen::VectorXd::LinSpaced(n, -1, 1),
              {},
              {}};
    DenseSymmetricSolver cholesky;
    DenseLuSolver lu;
    EXPECT_TRUE(cholesky.solve(item.a, 1e-6, item.b, item.cholesky).ok);
    EXPECT_TRUE(lu.solve(item.a, 1e-6, item.b, item.lu).ok);
    cases.push_back(std::move(item));
  }
  std::atomic<int> mismatches{0};
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t) {
    threads.emplace_back([&, t] {
      DenseSymmetricSolver cholesky;
      DenseLuSolver lu;
      for (int round = 0; round < 10; ++round) {
        for (std::size_t c = 0; c < cases.size(); ++c) {
          const Case& item = cases[(c + static_cast<std::size_t>(t)) % cases.size()];
          Eigen::VectorXd x, y;
          cholesky.solve(item.a, 1e-6, item.b, x);
          lu.solve(item.a, 1e-6, item.b, y);
          if (x != item.cholesky || y != item.lu) mismatches.fetch_add(1);
        }
      }
    });
  }
  for (std::thread& thread : threads) thread.join();
  EXPECT_EQ(mismatches.load(), 0);
}

}  // namespace
}  // namespace ggk::kernels
