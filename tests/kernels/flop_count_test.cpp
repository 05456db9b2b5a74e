#include "kernels/flop_count.hpp"

#include <gtest/gtest.h>

#include <vector>

#include "kernels/action_block_system.hpp"
#include "kernels/dense_solvers.hpp"
#include "kernels/random_stream.hpp"

namespace ggk::kernels {
namespace {

// The counter is the process's: a test reads what one call adds (the tests of
// this binary run one after the other).

TEST(FlopCount, ACholeskySolveCountsItsFactorization) {
  constexpr int n = 12;
  const Eigen::MatrixXd r = Eigen::MatrixXd::Random(n, n);
  const Eigen::MatrixXd a = r.transpose() * r + Eigen::MatrixXd::Identity(n, n);
  const Eigen::VectorXd b = Eigen::VectorXd::Ones(n);
  Eigen::VectorXd x;
  DenseSymmetricSolver solver;
  const double before = flops_counted();
  ASSERT_TRUE(solver.solve(a, 0.0, b, x).ok);
  EXPECT_EQ(flops_counted() - before, static_cast<double>(n * n * n / 3));  // n^3 / 3: 576
}

TEST(FlopCount, TheCopyBasisStartBlocksCountARankUpdateAndAProductPerSample) {
  // Every sample's row in its action's start block: a rank-1 update of the p x p
  // block (p (p + 1) flops) and its right-hand side (2 p).
  constexpr std::int32_t states = 30, actions = 3, p = 5, samples = 50;
  RandomStream rng(11, 0, 0);
  std::vector<Eigen::Triplet<double>> entries;
  for (std::int32_t s = 0; s < states; ++s) {
    for (std::int32_t j = 0; j < p; ++j) entries.emplace_back(s, j, 0.1 + rng.uniform());
  }
  SparseRowMatrix kernels(states, p);
  kernels.setFromTriplets(entries.begin(), entries.end());
  kernels.makeCompressed();
  SampleBatch batch;
  for (std::int32_t i = 0; i < samples; ++i) {
    batch.add(static_cast<std::int32_t>(rng.uniform_index(states)),
              static_cast<std::int32_t>(rng.uniform_index(actions)), rng.uniform(),
              static_cast<std::int32_t>(rng.uniform_index(states)), false, 1.0);
  }
  const double before = flops_counted();
  const auto fixed = ActionBlockSystem::copy_basis_fixed(kernels, actions, batch);
  EXPECT_EQ(flops_counted() - before, static_cast<double>(samples * (p * (p + 1) + 2 * p)));
}

}  // namespace
}  // namespace ggk::kernels
