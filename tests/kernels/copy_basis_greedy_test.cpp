#include "kernels/copy_basis_greedy.hpp"
#include "kernels/avx2_dispatch.hpp"

#include <cstdint>
#include <vector>

#include <gtest/gtest.h>

#include "kernels/lspi.hpp"
#include "kernels/random_stream.hpp"
#include "kernels/state_action_basis.hpp"
#include "support/near_tied_weights.hpp"

namespace ggk::kernels {
namespace {

// State kernels with dense rows (all p entries) in runs of random length, as
// untruncated kernels and proto-value functions give, between sparse rows and empty
// rows; 1,003 states, so the eight-row blocks end in a remainder.
SparseRowMatrix mixed_table(RandomStream& rng, Eigen::Index states, Eigen::Index p) {
  std::vector<Eigen::Triplet<double>> entries;
  bool dense = true;
  for (Eigen::Index s = 0; s < states; ++s) {
    if (rng.uniform() < 0.05) dense = !dense;
    for (Eigen::Index j = 0; j < p; ++j) {
      if (dense || rng.uniform() < 0.3) entries.emplace_back(s, j, rng.uniform());
    }
  }
  SparseRowMatrix table(states, p);
  table.setFromTriplets(entries.begin(), entries.end());
  table.makeCompressed();
  return table;
}

// Both instruction paths give greedy_policy's policy on the copy table, bit for bit,
// for 2, 3 and 4 actions (the AVX2 path serves 4; the others check the dispatch).
TEST(CopyBasisGreedy, EveryPathEqualsTheSparseProduct) {
  RecordProperty("avx2", cpu_has_avx2() ? "yes" : "no");
  RandomStream rng(43, 0, 0);
  for (const std::int32_t actions : {2, 3, 4}) {
    for (const Eigen::Index p : {1, 7, 16, 33}) {
      const SparseRowMatrix kernels = mixed_table(rng, 1003, p);
      const SparseRowMatrix features = copy_basis(kernels, actions);
      for (int trial = 0; trial < 6; ++trial) {
        const Eigen::VectorXd w = test_support::near_tied_weights(rng, p, actions, trial);
        const std::vector<std::int32_t> expected = greedy_policy(features, actions, w);
        EXPECT_EQ(copy_greedy(kernels, 1, p, actions, w, GreedyInstructions::automatic), expected)
            << actions << " actions, p " << p << ", trial " << trial;
        EXPECT_EQ(copy_greedy(kernels, 1, p, actions, w, GreedyInstructions::portable), expected)
            << actions << " actions, p " << p << ", trial " << trial;
        // The copy table read with a row step (copy_layout_greedy_policy's way).
        EXPECT_EQ(copy_greedy(features, actions, p, actions, w), expected)
            << actions << " actions, p " << p << ", trial " << trial;
      }
    }
  }
}

}  // namespace
}  // namespace ggk::kernels
