#include "kernels/state_action_basis.hpp"

#include <cmath>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

namespace ggk::kernels {
namespace {

SparseRowMatrix kernels_3x2() {
  // K(s, c) for 3 states and 2 centres, with one structural zero.
  Eigen::MatrixXd dense(3, 2);
  dense << 1.0, 0.2, 0.5, 0.0, 0.1, 0.9;
  return dense.sparseView();
}

TEST(StateActionBasis, CopyPlacesKernelsInTheActionBlock) {
  const SparseRowMatrix table = copy_basis(kernels_3x2(), 2);
  ASSERT_EQ(table.rows(), 6);
  ASSERT_EQ(table.cols(), 4);
  // Row s*m + a; column a*p + j.
  EXPECT_EQ(table.coeff(2 * 2 + 1, 1 * 2 + 1), 0.9);
  EXPECT_EQ(table.coeff(2 * 2 + 1, 0 * 2 + 1), 0.0);
  EXPECT_EQ(table.coeff(0 * 2 + 0, 0), 1.0);
  EXPECT_EQ(table.coeff(1 * 2 + 1, 2), 0.5);
  EXPECT_EQ(table.nonZeros(), 2 * 5);
}

TEST(StateActionBasis, ShiftAveragesKernelsOverObservedSuccessors) {
  // From state 0, action 1 leads to state 1 twice and state 2 once;
  // from state 2, action 0 leads to state 0. Everything else is unobserved.
  const std::vector<std::int32_t> s = {0, 0, 0, 2}, a = {1, 1, 1, 0}, next = {1, 1, 2, 0};
  const EmpiricalTransitionModel model(3, 2, s, a, next);
  const SparseRowMatrix table = shift_basis(kernels_3x2(), 2, model);
  // Eq. (9): phi_{1,j}(0, 1) = 2/3 K(1, c_j) + 1/3 K(2, c_j).
  EXPECT_DOUBLE_EQ(table.coeff(0 * 2 + 1, 2 + 0), 2.0 / 3.0 * 0.5 + 1.0 / 3.0 * 0.1);
  EXPECT_DOUBLE_EQ(table.coeff(0 * 2 + 1, 2 + 1), 1.0 / 3.0 * 0.9);
  EXPECT_DOUBLE_EQ(table.coeff(2 * 2 + 0, 0), 1.0);
  EXPECT_DOUBLE_EQ(table.coeff(2 * 2 + 0, 1), 0.2);
  // Unobserved (0, 0) falls back to copy.
  EXPECT_DOUBLE_EQ(table.coeff(0, 0), 1.0);
  EXPECT_DOUBLE_EQ(table.coeff(0, 1), 0.2);
  // Other action blocks stay empty.
  EXPECT_EQ(table.coeff(0 * 2 + 1, 0), 0.0);
}

// Every row of the shift basis is Eq. (9) summed as its definition: each centre's
// value starts at 0 and adds P(s'|s,a) K(s', c_j) successor by successor, and the
// row holds the union of the successors' non-zeros. Pairs with one successor (a
// deterministic task's, the arm's: a path of their own) and with two, unobserved
// pairs, and kernels with structural zeros.
TEST(StateActionBasis, ShiftRowsAreEquationNineBitForBit) {
  constexpr int kStates = 7, kCenters = 5, kActions = 3;
  Eigen::MatrixXd dense(kStates, kCenters);
  for (int i = 0; i < kStates; ++i) {
    for (int j = 0; j < kCenters; ++j) {
      dense(i, j) = (i + 2 * j) % 4 == 0 ? 0.0 : std::sin(1.0 + i * 0.7 + j * 1.3) * 0.5 + 0.5;
    }
  }
  const SparseRowMatrix kernels = dense.sparseView();
  // (s, a) -> s': (s + a + 1) % 7, twice; action 2 also to (s + 5) % 7 once from
  // even states; state 6 never takes action 1.
  std::vector<std::int32_t> s, a, next;
  for (int state = 0; state < kStates; ++state) {
    for (int action = 0; action < kActions; ++action) {
      if (state == 6 && action == 1) continue;
      for (int repeat = 0; repeat < 2; ++repeat) {
        s.push_back(state);
        a.push_back(action);
        next.push_back((state + action + 1) % kStates);
      }
      if (action == 2 && state % 2 == 0) {
        s.push_back(state);
        a.push_back(action);
        next.push_back((state + 5) % kStates);
      }
    }
  }
  const EmpiricalTransitionModel model(kStates, kActions, s, a, next);
  const SparseRowMatrix table = shift_basis(kernels, kActions, model);
  Eigen::MatrixXd expected = Eigen::MatrixXd::Zero(kStates * kActions, kCenters * kActions);
  Eigen::Index expected_nonzeros = 0;
  for (int state = 0; state < kStates; ++state) {
    for (int action = 0; action < kActions; ++action) {
      std::vector<double> sum(kCenters, 0.0);
      std::vector<bool> stored(kCenters, false);
      if (!model.observed(state, action)) {
        for (int j = 0; j < kCenters; ++j) {
          sum[static_cast<std::size_t>(j)] = dense(state, j);
          stored[static_cast<std::size_t>(j)] = dense(state, j) != 0.0;
        }
      } else {
        const auto successors = model.successors(state, action);
        const auto probabilities = model.probabilities(state, action);
        for (std::size_t e = 0; e < successors.size(); ++e) {
          for (int j = 0; j < kCenters; ++j) {
            if (dense(successors[e], j) == 0.0) continue;
            sum[static_cast<std::size_t>(j)] += probabilities[e] * dense(successors[e], j);
            stored[static_cast<std::size_t>(j)] = true;
          }
        }
      }
      for (int j = 0; j < kCenters; ++j) {
        expected(state * kActions + action, action * kCenters + j) =
            sum[static_cast<std::size_t>(j)];
        expected_nonzeros += stored[static_cast<std::size_t>(j)] ? 1 : 0;
      }
    }
  }
  EXPECT_EQ(Eigen::MatrixXd(table), expected);
  EXPECT_EQ(table.nonZeros(), expected_nonzeros);
  EXPECT_EQ(model.successors(0, 0).size(), 1u);  // both paths are exercised
  EXPECT_EQ(model.successors(0, 2).size(), 2u);
}

TEST(StateActionBasis, ShiftEqualsCopyWhenEveryTransitionIsASelfLoop) {
  std::vector<std::int32_t> s, a;
  for (std::int32_t state = 0; state < 3; ++state) {
    for (std::int32_t action = 0; action < 2; ++action) {
      s.push_back(state);
      a.push_back(action);
    }
  }
  const EmpiricalTransitionModel model(3, 2, s, a, s);
  const SparseRowMatrix shifted = shift_basis(kernels_3x2(), 2, model);
  const SparseRowMatrix copied = copy_basis(kernels_3x2(), 2);
  EXPECT_EQ(Eigen::MatrixXd(shifted), Eigen::MatrixXd(copied));
}

TEST(StateActionBasis, RejectsMismatchedModel) {
  const std::vector<std::int32_t> none;
  const EmpiricalTransitionModel model(4, 2, none, none, none);
  EXPECT_THROW(shift_basis(kernels_3x2(), 2, model), std::invalid_argument);
  EXPECT_THROW(copy_basis(kernels_3x2(), 0), std::invalid_argument);
}

}  // namespace
}  // namespace ggk::kernels
