// The greedy steps (kernels/copy_basis_greedy.cpp, kernels/action_block_greedy.cpp)
// compiled for a machine target with FMA (tests/CMakeLists.txt builds them into this
// executable with -march=haswell). There the compiler may fuse a multiply and an add
// into one rounding wherever contraction is allowed; the build turns it off
// (-ffp-contract=off, cmake/GgkTarget.cmake), so every Q(s, a) is still a rounded
// multiply then a rounded add per entry, in entry order: the AVX2 path, the portable
// path and the reference below give the same policy bit for bit.
//
// The reference forms each product through a volatile, so it is rounded to a double
// whatever the flags of this file; near-tied weights (support/near_tied_weights.hpp)
// rank actions differently under one fused multiply-add.

#include <cstdint>
#include <vector>

#include <gtest/gtest.h>

#include "kernels/action_block_greedy.hpp"
#include "kernels/avx2_dispatch.hpp"
#include "kernels/copy_basis_greedy.hpp"
#include "kernels/first_best.hpp"
#include "kernels/random_stream.hpp"
#include "support/near_tied_weights.hpp"

namespace ggk::kernels {
namespace {

bool cpu_runs_haswell_code() {
#if GGK_AVX2_DISPATCH
  return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
#else
  return false;
#endif
}

// Q(s, a) of row `row`: from 0, each entry's rounded product then a rounded add.
double unfused_row_sum(const SparseRowMatrix& table, Eigen::Index row,
                       const Eigen::VectorXd& weights, Eigen::Index column_offset) {
  double sum = 0.0;
  for (SparseRowMatrix::InnerIterator it(table, row); it; ++it) {
    volatile double product = it.value() * weights(column_offset + it.index());
    sum += product;
  }
  return sum;
}

// Dense rows in runs (the paths' side-by-side sums), sparse and empty rows between.
SparseRowMatrix mixed_table(RandomStream& rng, Eigen::Index rows, Eigen::Index p) {
  std::vector<Eigen::Triplet<double>> entries;
  bool dense = true;
  for (Eigen::Index s = 0; s < rows; ++s) {
    if (rng.uniform() < 0.05) dense = !dense;
    for (Eigen::Index j = 0; j < p; ++j) {
      if (dense || rng.uniform() < 0.3) entries.emplace_back(s, j, rng.uniform());
    }
  }
  SparseRowMatrix table(rows, p);
  table.setFromTriplets(entries.begin(), entries.end());
  table.makeCompressed();
  return table;
}

TEST(FmaTargetGreedy, CopyGreedyPathsEqualTheUnfusedSums) {
  if (!cpu_runs_haswell_code()) GTEST_SKIP() << "this CPU lacks AVX2 or FMA";
  RandomStream rng(71, 0, 0);
  const std::int32_t m = 4;  // the AVX2 path's action count
  for (const Eigen::Index p : {7, 16, 33}) {
    const SparseRowMatrix kernels = mixed_table(rng, 1003, p);
    for (int trial = 0; trial < 8; ++trial) {
      const Eigen::VectorXd w = test_support::near_tied_weights(rng, p, m, trial);
      std::vector<std::int32_t> expected(static_cast<std::size_t>(kernels.rows()));
      for (Eigen::Index s = 0; s < kernels.rows(); ++s) {
        double q[m];
        for (std::int32_t a = 0; a < m; ++a) q[a] = unfused_row_sum(kernels, s, w, a * p);
        expected[static_cast<std::size_t>(s)] = first_best(q, m);
      }
      EXPECT_EQ(copy_greedy(kernels, 1, p, m, w, GreedyInstructions::automatic), expected)
          << "AVX2 path, p " << p << ", trial " << trial;
      EXPECT_EQ(copy_greedy(kernels, 1, p, m, w, GreedyInstructions::portable), expected)
          << "portable path, p " << p << ", trial " << trial;
    }
  }
}

TEST(FmaTargetGreedy, ActionBlockGreedyEqualsTheUnfusedSums) {
  if (!cpu_runs_haswell_code()) GTEST_SKIP() << "this CPU lacks AVX2 or FMA";
  RandomStream rng(73, 0, 0);
  for (const std::int32_t m : {2, 4}) {
    for (const Eigen::Index p : {6, 32}) {
      // Action a's rows hold the state's values in columns [a p, (a + 1) p).
      const SparseRowMatrix states = mixed_table(rng, 701, p);
      std::vector<Eigen::Triplet<double>> entries;
      for (Eigen::Index s = 0; s < states.rows(); ++s) {
        for (std::int32_t a = 0; a < m; ++a) {
          for (SparseRowMatrix::InnerIterator it(states, s); it; ++it) {
            entries.emplace_back(s * m + a, a * p + it.index(), it.value());
          }
        }
      }
      SparseRowMatrix table(states.rows() * m, m * p);
      table.setFromTriplets(entries.begin(), entries.end());
      table.makeCompressed();
      for (int trial = 0; trial < 8; ++trial) {
        const Eigen::VectorXd w = test_support::near_tied_weights(rng, p, m, trial);
        std::vector<std::int32_t> expected(static_cast<std::size_t>(states.rows()));
        std::vector<double> q(static_cast<std::size_t>(m));
        for (Eigen::Index s = 0; s < states.rows(); ++s) {
          for (std::int32_t a = 0; a < m; ++a) {
            q[static_cast<std::size_t>(a)] = unfused_row_sum(table, s * m + a, w, 0);
          }
          expected[static_cast<std::size_t>(s)] = first_best(q.data(), m);
        }
        EXPECT_EQ(action_block_greedy(table, m, w), expected)
            << m << " actions, p " << p << ", trial " << trial;
      }
    }
  }
}

}  // namespace
}  // namespace ggk::kernels
