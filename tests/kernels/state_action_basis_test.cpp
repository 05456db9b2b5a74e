#include "kernels/state_action_basis.hpp"

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
