#pragma once
// Weights for the greedy-step tests (copy_basis_greedy_test, action_block_greedy_test):
// actions whose weights differ in the last bits only (odd trials) or not at all (even
// trials, where Q values tie wherever the actions' rows hold the same values). Another
// order of the sums, a fused multiply-add or another tie rule ranks these differently.

#include <cstdint>

#include <Eigen/Core>

#include "kernels/random_stream.hpp"

namespace ggk::test_support {

inline Eigen::VectorXd near_tied_weights(kernels::RandomStream& rng, Eigen::Index p,
                                         std::int32_t actions, int trial) {
  Eigen::VectorXd w(p * actions);
  for (Eigen::Index j = 0; j < p; ++j) {
    const double base = rng.uniform(-1, 1);
    for (std::int32_t a = 0; a < actions; ++a) {
      w(a * p + j) =
          trial % 2 == 0 ? base : base * (1.0 + 1e-15 * static_cast<double>(rng.uniform_index(3)));
    }
  }
  return w;
}

}  // namespace ggk::test_support
