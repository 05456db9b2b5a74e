// The chain walk (sims/chain/chain.hpp): moves and dead ends, the reward for
// entering a rewarded state, the success probability's statistics, and the
// optimal actions by value iteration: for the paper's 20-state chain, left in
// states 1-10 and right in 11-20; ties make both actions optimal.

#include "sims/chain/chain.hpp"

#include <array>
#include <cstdint>
#include <vector>

#include <gtest/gtest.h>

namespace ggk::sims::chain {
namespace {

TEST(Chain, MovesOneStateAndTheEndsAreDeadEnds) {
  const Chain chain{ChainConfig{}};
  EXPECT_EQ(chain.num_states(), 20);
  EXPECT_EQ(chain.move(5, kRight, true), 6);
  EXPECT_EQ(chain.move(5, kRight, false), 4);
  EXPECT_EQ(chain.move(5, kLeft, true), 4);
  EXPECT_EQ(chain.move(5, kLeft, false), 6);
  EXPECT_EQ(chain.move(0, kLeft, true), 0);
  EXPECT_EQ(chain.move(0, kRight, false), 0);
  EXPECT_EQ(chain.move(19, kRight, true), 19);
  EXPECT_EQ(chain.move(19, kLeft, false), 19);
}

TEST(Chain, RewardForEnteringTheEnds) {
  const Chain chain{ChainConfig{}};
  for (std::int32_t s = 0; s < 20; ++s) {
    EXPECT_EQ(chain.reward(s), s == 0 || s == 19 ? 1.0 : 0.0) << s;
  }
}

TEST(Chain, MovesGoTheIntendedWayWithTheSuccessProbability) {
  const Chain chain{ChainConfig{}};
  kernels::RandomStream random(42, 0, 0);
  const int draws = 100'000;
  int intended = 0;
  for (int i = 0; i < draws; ++i) {
    const StepResult r = chain.step(10, kRight, random);
    ASSERT_TRUE(r.next_state == 11 || r.next_state == 9);
    intended += r.next_state == 11;
  }
  // 0.9 +- 5 standard deviations (sd = sqrt(0.09 / draws) ~ 0.00095).
  EXPECT_NEAR(intended / static_cast<double>(draws), 0.9, 0.005);
}

TEST(Chain, OptimalPolicyOfThePapersTwentyStateChain) {
  const Chain chain{ChainConfig{}};
  const std::vector<std::array<bool, kNumActions>> optimal = chain.optimal_actions(0.9);
  ASSERT_EQ(optimal.size(), 20u);
  for (std::size_t s = 0; s < 20; ++s) {
    // The paper's states 1-10 (0-based 0-9) go left, 11-20 right; no ties.
    EXPECT_EQ(optimal[s][kLeft], s < 10) << "state " << s + 1;
    EXPECT_EQ(optimal[s][kRight], s >= 10) << "state " << s + 1;
  }
}

TEST(Chain, TiesMakeBothActionsOptimal) {
  ChainConfig config;
  config.success = 0.5;  // both actions the same coin: every Q* ties
  const Chain coin(config);
  for (const auto& actions : coin.optimal_actions(0.9)) {
    EXPECT_TRUE(actions[kLeft] && actions[kRight]);
  }
  // One rewarded state in the middle of 5: the middle state ties (both ways
  // lead away and back the same), left of it right, right of it left.
  config.success = 0.9;
  config.states = 5;
  config.rewarded = {2};
  const std::vector<std::array<bool, kNumActions>> middle = Chain(config).optimal_actions(0.9);
  EXPECT_TRUE(middle[2][kLeft] && middle[2][kRight]);
  EXPECT_TRUE(middle[0][kRight] && !middle[0][kLeft]);
  EXPECT_TRUE(middle[1][kRight] && !middle[1][kLeft]);
  EXPECT_TRUE(middle[3][kLeft] && !middle[3][kRight]);
  EXPECT_TRUE(middle[4][kLeft] && !middle[4][kRight]);
}

}  // namespace
}  // namespace ggk::sims::chain
