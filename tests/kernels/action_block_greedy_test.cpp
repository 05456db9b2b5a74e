#include "kernels/action_block_greedy.hpp"

#include <cstdint>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

#include "kernels/lspi.hpp"
#include "kernels/random_stream.hpp"
#include "support/near_tied_weights.hpp"

namespace ggk::kernels {
namespace {

// An action-block table of 701 states: row s m + a dense in block a (all p
// entries), sparse, or empty, in runs, so that states with every row dense (the
// side-by-side sums) alternate with states that take the row loop. A state's rows
// hold the same values (as a copy table's, or a shift table's of one successor),
// so that near-tied weights give near-tied Q values.
SparseRowMatrix block_table(RandomStream& rng, Eigen::Index states, std::int32_t m,
                            Eigen::Index p) {
  std::vector<Eigen::Triplet<double>> entries;
  bool dense = true;
  std::vector<double> values(static_cast<std::size_t>(p));
  for (Eigen::Index s = 0; s < states; ++s) {
    if (rng.uniform() < 0.1) dense = !dense;
    for (double& value : values) value = rng.uniform(-1, 1);
    for (std::int32_t a = 0; a < m; ++a) {
      const Eigen::Index row = s * m + a;
      const bool empty = !dense && rng.uniform() < 0.2;
      for (Eigen::Index j = 0; j < p && !empty; ++j) {
        if (dense || rng.uniform() < 0.4) {
          entries.emplace_back(row, a * p + j, values[static_cast<std::size_t>(j)]);
        }
      }
    }
  }
  SparseRowMatrix table(states * m, m * p);
  table.setFromTriplets(entries.begin(), entries.end());
  table.makeCompressed();
  return table;
}

// The policy of greedy_policy (features * w, then the first largest Q per state),
// bit for bit, for 2 to 4 actions (the side-by-side sums) and 5 (the row loop).
TEST(ActionBlockGreedy, EqualsTheSparseProductsPolicy) {
  RandomStream rng(53, 0, 0);
  for (const std::int32_t m : {2, 3, 4, 5}) {
    for (const Eigen::Index p : {1, 6, 32}) {
      const SparseRowMatrix table = block_table(rng, 701, m, p);
      for (int trial = 0; trial < 6; ++trial) {
        const Eigen::VectorXd w = test_support::near_tied_weights(rng, p, m, trial);
        EXPECT_EQ(action_block_greedy(table, m, w), greedy_policy(table, m, w))
            << m << " actions, p " << p << ", trial " << trial;
      }
    }
  }
}

TEST(ActionBlockGreedy, RefusesInconsistentShapes) {
  RandomStream rng(59, 0, 0);
  const SparseRowMatrix table = block_table(rng, 10, 4, 3);
  EXPECT_THROW(action_block_greedy(table, 4, Eigen::VectorXd::Zero(11)), std::invalid_argument);
  EXPECT_THROW(action_block_greedy(table, 0, Eigen::VectorXd::Zero(12)), std::invalid_argument);
  EXPECT_THROW(action_block_greedy(table, 5, Eigen::VectorXd::Zero(12)), std::invalid_argument);
  SparseRowMatrix uncompressed = table;
  uncompressed.uncompress();
  EXPECT_THROW(action_block_greedy(uncompressed, 4, Eigen::VectorXd::Zero(12)),
               std::invalid_argument);
}

}  // namespace
}  // namespace ggk::kernels
