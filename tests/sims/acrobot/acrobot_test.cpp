// The acrobot (sims/acrobot) against Gymnasium Acrobot-v1's update, run for a
// fixed action sequence by a numpy transcription of its source
// (gymnasium/envs/classic_control/acrobot.py: _dsdt "book", rk4, wrap, bound;
// tests/sims/acrobot/gymnasium_acrobot_reference.py): to 1e-12, through the angle
// wraps and the velocity clips; and the terminal edge.

#include "sims/acrobot/acrobot.hpp"

#include <cmath>
#include <numbers>
#include <vector>

#include <gtest/gtest.h>

namespace ggk::sims::acrobot {
namespace {

void expect_near(const State& a, const State& b) {
  for (std::size_t i = 0; i < 4; ++i) EXPECT_NEAR(a[i], b[i], 1e-12) << "component " << i;
}

State run(State s, const std::vector<int>& actions, std::size_t steps) {
  const AcrobotConfig c;
  for (std::size_t k = 0; k < steps; ++k) s = step(c, s, actions[k] - 1.0);
  return s;
}

TEST(Acrobot, FollowsGymnasiumsUpdate) {
  const std::vector<int> actions = {2, 2, 0, 0, 1, 2, 0, 2, 2, 2, 0, 0, 2, 2, 1, 0, 2, 0, 2, 2};
  const State start = {0.05, -0.03, 0.02, -0.01};
  expect_near(run(start, actions, 1), {0.033939211630615466, 0.0101677904243258,
                                       -0.17583183080297707, 0.40177497965573855});
  expect_near(run(start, actions, 5),
              {-0.01415158066541021, 0.05539872191822599, 0.217219552826865, -0.6403959502371137});
  expect_near(run(start, actions, 10), {-0.05258731313262108, 0.04494082471478694,
                                        -0.39932640058697827, 0.9540707089629332});
  expect_near(run(start, actions, 20),
              {0.028688192573248686, -0.01141509453997036, -0.424085708047822, 0.7008092551638925});
}

TEST(Acrobot, WrapsAnglesAndClipsVelocitiesAsGymnasium) {
  const std::vector<int> actions = {2, 2, 0, 1, 2};
  const State start = {3.1, -3.1, 12.0, -27.0};
  const std::vector<State> expected = {
      {-0.19985119704193721, 2.8588662883240925, 12.566370614359172, -28.274333882308138},
      {2.2162759910764303, -2.6730801324393783, 10.685379054835865, -25.508231087463052},
      {-1.3488950495256438, -2.754270905524729, 12.566370614359172, -28.274333882308138},
      {1.9527894201056206, 2.4222243296939645, 12.566370614359172, -28.274333882308138},
      {-2.0754039222322795, -2.6571319867605121, 8.4515923229796037, -19.176171896586617}};
  for (std::size_t k = 0; k < expected.size(); ++k) {
    SCOPED_TRACE(k);
    const State s = run(start, actions, k + 1);
    expect_near(s, expected[k]);
    EXPECT_LE(std::abs(s[0]), std::numbers::pi);
    EXPECT_LE(std::abs(s[2]), kMaxVelocity1);
    EXPECT_LE(std::abs(s[3]), kMaxVelocity2);
  }
  EXPECT_EQ(run(start, actions, 1)[2], kMaxVelocity1);  // clipped exactly at the limit
}

TEST(Acrobot, TerminalWhenTheTipRisesAboveTheBar) {
  EXPECT_FALSE(tip_above_bar({0.0, 0.0, 0.0, 0.0}));              // hanging: -2
  EXPECT_TRUE(tip_above_bar({std::numbers::pi, 0.0, 0.0, 0.0}));  // upright: 2
  // theta1 = pi / 2 (horizontal), theta2 bent up: 0 - cos(pi/2 + t2) = sin(t2).
  EXPECT_FALSE(tip_above_bar({std::numbers::pi / 2, std::numbers::pi / 2, 0.0, 0.0}));
  EXPECT_TRUE(tip_above_bar({2.2, 0.6, 0.0, 0.0}));
  const std::array<double, 6> o = observation({0.3, -0.2, 1.5, -2.5});
  EXPECT_EQ(o[0], std::cos(0.3));
  EXPECT_EQ(o[3], std::sin(-0.2));
  EXPECT_EQ(o[4], 1.5);
  EXPECT_EQ(o[5], -2.5);
}

}  // namespace
}  // namespace ggk::sims::acrobot
