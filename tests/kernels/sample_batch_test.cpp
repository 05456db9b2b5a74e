#include "kernels/sample_batch.hpp"

#include <limits>
#include <stdexcept>

#include <gtest/gtest.h>

namespace ggk::kernels {
namespace {

TEST(SampleBatch, FoldingMergesIdenticalTransitionsInFirstSeenOrder) {
  SampleBatch batch;
  batch.add(0, 1, 0.0, 2, false);
  batch.add(3, 0, 1.0, 4, true);
  batch.add(0, 1, 0.0, 2, false);
  batch.add(0, 1, 0.0, 2, true);   // differs in terminal
  batch.add(0, 1, 0.5, 2, false);  // differs in reward
  batch.add(3, 0, 1.0, 4, true, 2.5);
  const SampleBatch folded = fold_duplicate_samples(batch);
  ASSERT_EQ(folded.size(), 4u);
  EXPECT_EQ(folded.states, (std::vector<std::int32_t>{0, 3, 0, 0}));
  EXPECT_EQ(folded.weights, (std::vector<double>{2.0, 3.5, 1.0, 1.0}));
  EXPECT_EQ(folded.terminals, (std::vector<std::uint8_t>{0, 1, 1, 0}));
  EXPECT_EQ(folded.rewards, (std::vector<double>{0.0, 1.0, 0.0, 0.5}));
}

TEST(SampleBatch, ValidateNamesTheProblem) {
  SampleBatch batch;
  batch.add(0, 0, 0.0, 1, false);
  EXPECT_NO_THROW(batch.validate(2, 1));
  try {
    batch.validate(1, 1);
    FAIL() << "expected an error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("sample 0"), std::string::npos) << e.what();
  }
  batch.add(0, 1, 0.0, 1, false);
  EXPECT_THROW(batch.validate(2, 1), std::invalid_argument);  // action out of range
  SampleBatch nan_reward;
  nan_reward.add(0, 0, std::numeric_limits<double>::quiet_NaN(), 0, false);
  EXPECT_THROW(nan_reward.validate(1, 1), std::invalid_argument);
  SampleBatch zero_weight;
  zero_weight.add(0, 0, 0.0, 0, false, 0.0);
  EXPECT_THROW(zero_weight.validate(1, 1), std::invalid_argument);
  SampleBatch ragged = zero_weight;
  ragged.rewards.push_back(1.0);
  EXPECT_THROW(ragged.validate(1, 1), std::invalid_argument);
}

}  // namespace
}  // namespace ggk::kernels
