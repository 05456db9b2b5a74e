#include "kernels/transition_model.hpp"

#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

namespace ggk::kernels {
namespace {

TEST(EmpiricalTransitionModel, FrequenciesPerStateAction) {
  // (s, a, s'): (0,1,2) x2, (0,1,1) x1, (2,0,2) x1.
  const std::vector<std::int32_t> s = {0, 0, 2, 0}, a = {1, 1, 0, 1}, next = {2, 1, 2, 2};
  const EmpiricalTransitionModel model(3, 2, s, a, next);
  EXPECT_FALSE(model.observed(0, 0));
  EXPECT_FALSE(model.observed(1, 1));
  ASSERT_TRUE(model.observed(0, 1));
  EXPECT_EQ(std::vector<std::int32_t>(model.successors(0, 1).begin(), model.successors(0, 1).end()),
            (std::vector<std::int32_t>{1, 2}));
  EXPECT_DOUBLE_EQ(model.probabilities(0, 1)[0], 1.0 / 3.0);
  EXPECT_DOUBLE_EQ(model.probabilities(0, 1)[1], 2.0 / 3.0);
  EXPECT_DOUBLE_EQ(model.probabilities(2, 0)[0], 1.0);
}

TEST(EmpiricalTransitionModel, WeightsCountAsRepetitions) {
  const std::vector<std::int32_t> s = {0, 0}, a = {0, 0}, next = {0, 1};
  const std::vector<double> w = {3.0, 1.0};
  const EmpiricalTransitionModel model(2, 1, s, a, next, w);
  EXPECT_DOUBLE_EQ(model.probabilities(0, 0)[0], 0.75);
  EXPECT_DOUBLE_EQ(model.probabilities(0, 0)[1], 0.25);
}

TEST(EmpiricalTransitionModel, RejectsBadInput) {
  const std::vector<std::int32_t> s = {0}, a = {2}, next = {0}, two = {0, 0};
  EXPECT_THROW(EmpiricalTransitionModel(1, 2, s, a, next), std::invalid_argument);
  EXPECT_THROW(EmpiricalTransitionModel(1, 3, s, a, two), std::invalid_argument);
  const std::vector<double> zero = {0.0};
  EXPECT_THROW(EmpiricalTransitionModel(1, 3, s, a, next, zero), std::invalid_argument);
}

}  // namespace
}  // namespace ggk::kernels
