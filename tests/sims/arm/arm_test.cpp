#include "sims/arm/arm.hpp"

#include <cmath>
#include <numbers>
#include <string>
#include <tuple>
#include <vector>

#include <gtest/gtest.h>

#include "sims/arm/arm_test_helpers.hpp"

#include "sims/arm/arm_geometry.hpp"
#include "sims/arm/collision.hpp"
#include "sims/arm/kinematics.hpp"

namespace ggk::sims::arm {
namespace {

using namespace test_helpers;

// A 5 x 5 grid (shoulder 0..20, elbow -10..10) with unit links from the origin:
// a tiny disc on the middle of link 1 at shoulder 10 blocks that whole row (at
// shoulder 5 or 15 link 1 passes it at 0.5 sin 5 deg = 0.044), and a tiny object
// at the end effector of (20, 0) makes that pose the only goal ((15, 10) points
// the same way but reaches 2 cos 5 deg, 0.0076 short).
ArmConfig small_config() {
  ArmConfig config;
  config.limits = {0, 20, -10, 10};
  config.geometry.obstacles = {Disc{{0.5 * std::cos(deg(10)), 0.5 * std::sin(deg(10))}, 0.01}};
  config.geometry.object = {{2.0 * std::cos(deg(20)), 2.0 * std::sin(deg(20))}, 0.005};
  config.start_A = {0, -10};
  return config;
}

TEST(Arm, NumbersFreeCellsRowMajor) {
  const Arm arm(small_config());
  EXPECT_EQ(arm.shoulder_steps(), 5);
  EXPECT_EQ(arm.elbow_steps(), 5);
  EXPECT_EQ(arm.num_actions(), 4);
  ASSERT_EQ(arm.num_states(), 20);
  EXPECT_EQ(arm.state_of(0, 0), 0);
  EXPECT_EQ(arm.state_of(1, 4), 9);
  EXPECT_EQ(arm.state_of(2, 0), kNoState);  // shoulder 10 collides
  EXPECT_EQ(arm.state_of(2, 4), kNoState);
  EXPECT_EQ(arm.state_of(3, 0), 10);
  EXPECT_EQ(arm.state_of(4, 2), 17);
  EXPECT_EQ(arm.state_of(-1, 0), kNoState);
  EXPECT_EQ(arm.state_of(0, 5), kNoState);
  EXPECT_TRUE(arm.collides(2, 3));
  EXPECT_FALSE(arm.collides(3, 3));
  EXPECT_THROW(arm.collides(5, 0), std::out_of_range);

  EXPECT_EQ(arm.cell_of(11), (GridCell{3, 1}));
  EXPECT_EQ(arm.angles_of(11), (JointAngles{15, -5}));
  EXPECT_EQ(arm.angles_of(0), (JointAngles{0, -10}));
  EXPECT_THROW(arm.cell_of(20), std::out_of_range);
  EXPECT_THROW(arm.angles_of(-1), std::out_of_range);

  // State vectors are the angles in units of 5 degrees (grid units at the default step).
  EXPECT_EQ(arm.state_vector(11), (std::array<double, 2>{3.0, -1.0}));
  const kernels::RowMatrixXd vectors = arm.state_vectors();
  ASSERT_EQ(vectors.rows(), 20);
  ASSERT_EQ(vectors.cols(), 2);
  for (std::int32_t s = 0; s < arm.num_states(); ++s) {
    const JointAngles angles = arm.angles_of(s);
    EXPECT_EQ(vectors(s, 0), angles.shoulder_deg / 5.0);
    EXPECT_EQ(vectors(s, 1), angles.elbow_deg / 5.0);
  }

  EXPECT_EQ(arm.goal_states(), std::vector<std::int32_t>{17});
  EXPECT_TRUE(arm.is_goal(17));
  EXPECT_FALSE(arm.is_goal(16));
  EXPECT_EQ(arm.start_state_A(), 0);
  const ArmPose pose = arm.pose_of(17);
  EXPECT_NEAR(pose.end_effector.x, 2.0 * std::cos(deg(20)), kTol);
}

TEST(Arm, BlockedAndLimitMovesStayPut) {
  const Arm arm(small_config());
  const std::int32_t corner = arm.state_of(0, 0);
  EXPECT_EQ(arm.move(corner, kShoulderMinus), corner);  // shoulder limit 0
  EXPECT_EQ(arm.move(corner, kElbowMinus), corner);     // elbow limit -10
  EXPECT_EQ(arm.move(corner, kShoulderPlus), arm.state_of(1, 0));
  EXPECT_EQ(arm.move(corner, kElbowPlus), arm.state_of(0, 1));
  const std::int32_t top = arm.state_of(4, 4);
  EXPECT_EQ(arm.move(top, kShoulderPlus), top);  // shoulder limit 20
  EXPECT_EQ(arm.move(top, kElbowPlus), top);     // elbow limit 10
  // Shoulder 5 -> 10 and 15 -> 10 collide.
  const std::int32_t below = arm.state_of(1, 3);
  const std::int32_t above = arm.state_of(3, 3);
  const StepResult blocked = arm.step(below, kShoulderPlus);
  EXPECT_EQ(blocked.next_state, below);
  EXPECT_EQ(blocked.reward, 0.0);
  EXPECT_FALSE(blocked.terminal);
  EXPECT_EQ(arm.step(above, kShoulderMinus).next_state, above);
  EXPECT_THROW(arm.step(below, 4), std::out_of_range);
  EXPECT_THROW(arm.step(below, -1), std::out_of_range);
  EXPECT_THROW(arm.step(20, kElbowPlus), std::out_of_range);
}

TEST(Arm, EnteringTheGoalPaysOneAndEndsTheEpisode) {
  const Arm arm(small_config());
  const std::int32_t goal = arm.state_of(4, 2);
  for (const auto& [from, action] :
       {std::pair{arm.state_of(4, 1), kElbowPlus}, std::pair{arm.state_of(4, 3), kElbowMinus},
        std::pair{arm.state_of(3, 2), kShoulderPlus}}) {
    const StepResult r = arm.step(from, action);
    EXPECT_EQ(r.next_state, goal);
    EXPECT_EQ(r.reward, 1.0);
    EXPECT_TRUE(r.terminal);
  }
  const StepResult plain = arm.step(arm.state_of(3, 2), kElbowPlus);
  EXPECT_EQ(plain.reward, 0.0);
  EXPECT_FALSE(plain.terminal);
  // From a goal (never a start in the protocol): terminal, no new reward.
  const StepResult stay = arm.step(goal, kShoulderPlus);
  EXPECT_EQ(stay.next_state, goal);
  EXPECT_EQ(stay.reward, 0.0);
  EXPECT_TRUE(stay.terminal);
}

TEST(Arm, GridMatchesDirectCollisionTests) {
  ArmConfig config;  // the default 37 x 72 grid
  config.geometry.obstacles = {Rectangle{{-3.0, -2.0}, {3.0, -0.1}}, Disc{{0.0, 1.6}, 0.3},
                               Rectangle{{-1.6, -0.1}, {-0.9, 0.5}}};
  config.geometry.object = {{1.25, 0.2}, 0.2};
  config.start_A = {110, 0};
  const Arm arm(config);
  ASSERT_EQ(arm.shoulder_steps(), 37);
  ASSERT_EQ(arm.elbow_steps(), 72);
  std::int32_t expected_state = 0;
  for (std::int32_t i = 0; i < 37; ++i) {
    for (std::int32_t j = 0; j < 72; ++j) {
      const ArmPose pose = forward_kinematics(config.geometry, 5.0 * i, -180.0 + 5.0 * j);
      const bool collides = arm_collides(config.geometry, pose);
      ASSERT_EQ(arm.collides(i, j), collides) << i << ", " << j;
      if (collides) continue;
      const std::int32_t s = arm.state_of(i, j);
      ASSERT_EQ(s, expected_state++);
      EXPECT_EQ(arm.is_goal(s), touches_object(config.geometry, pose));
    }
  }
  EXPECT_EQ(arm.num_states(), expected_state);
}

// small_config() on a 2.5-degree grid: 9 x 9 cells (shoulder 0, 2.5, ..., 20;
// elbow -10, -7.5, ..., 10). The disc still blocks the row at shoulder 10 only
// (at 7.5 and 12.5 link 1 passes it at 0.5 sin 2.5 deg = 0.022 > 0.01). The end
// effector points at 20 degrees from (20, 0), reaching 2, and from (17.5, 5),
// reaching 2 cos 2.5 deg (0.0019 short, inside the object's 0.005): two goals;
// (15, 10) still falls 0.0076 short.
ArmConfig fine_config() {
  ArmConfig config = small_config();
  config.grid_step_tenths = 25;
  return config;
}

TEST(ArmFineGrid, GridOfTwoAndAHalfDegrees) {
  const Arm arm(fine_config());
  EXPECT_EQ(arm.grid_step_tenths(), 25);
  EXPECT_EQ(arm.grid_step_degrees(), 2.5);
  EXPECT_EQ(arm.shoulder_steps(), 9);
  EXPECT_EQ(arm.elbow_steps(), 9);
  ASSERT_EQ(arm.num_states(), 72);  // 81 cells less the row at shoulder 10
  for (std::int32_t j = 0; j < 9; ++j) {
    EXPECT_TRUE(arm.collides(4, j)) << j;
    EXPECT_FALSE(arm.collides(3, j)) << j;
    EXPECT_FALSE(arm.collides(5, j)) << j;
  }
  EXPECT_EQ(arm.state_of(3, 8), 35);
  EXPECT_EQ(arm.state_of(5, 0), 36);
  // Goals (17.5, 5) = cell (7, 6) and (20, 0) = cell (8, 4).
  EXPECT_EQ(arm.goal_states(), (std::vector<std::int32_t>{36 + 2 * 9 + 6, 36 + 3 * 9 + 4}));
  EXPECT_EQ(arm.angles_of(60), (JointAngles{17.5, 5.0}));
  EXPECT_EQ(arm.angles_of(67), (JointAngles{20.0, 0.0}));

  // A hand-checked pose: cell (1, 3) is shoulder 2.5, elbow -2.5.
  const std::int32_t s = arm.state_of(1, 3);
  EXPECT_EQ(arm.angles_of(s), (JointAngles{2.5, -2.5}));
  // State vectors stay in units of 5 degrees: neighbours are 0.5 apart.
  EXPECT_EQ(arm.state_vector(s), (std::array<double, 2>{0.5, -0.5}));
  const ArmPose pose = arm.pose_of(s);
  expect_point(pose.elbow, std::cos(deg(2.5)), std::sin(deg(2.5)));
  expect_point(pose.end_effector, std::cos(deg(2.5)) + 1.0, std::sin(deg(2.5)));  // forearm at 0
}

TEST(ArmFineGrid, ActionsTurnOneJointByOneStep) {
  const Arm arm(fine_config());
  const std::int32_t s = arm.state_of(1, 3);  // (2.5, -2.5)
  EXPECT_EQ(arm.angles_of(arm.move(s, kShoulderPlus)), (JointAngles{5.0, -2.5}));
  EXPECT_EQ(arm.angles_of(arm.move(s, kShoulderMinus)), (JointAngles{0.0, -2.5}));
  EXPECT_EQ(arm.angles_of(arm.move(s, kElbowPlus)), (JointAngles{2.5, 0.0}));
  EXPECT_EQ(arm.angles_of(arm.move(s, kElbowMinus)), (JointAngles{2.5, -5.0}));
  // Shoulder 7.5 -> 10 collides; the limits stop moves as on the 5-degree grid.
  const std::int32_t below = arm.state_of(3, 0);
  EXPECT_EQ(arm.move(below, kShoulderPlus), below);
  EXPECT_EQ(arm.move(arm.state_of(8, 8), kElbowPlus), arm.state_of(8, 8));
  const StepResult r = arm.step(arm.state_of(7, 5), kElbowPlus);  // (17.5, 2.5) -> (17.5, 5)
  EXPECT_EQ(r.next_state, 60);
  EXPECT_EQ(r.reward, 1.0);
  EXPECT_TRUE(r.terminal);
}

TEST(ArmFineGrid, GridMatchesDirectCollisionTestsAtEveryStep) {
  ArmConfig config;  // the default limits
  config.geometry.obstacles = {Rectangle{{-3.0, -2.0}, {3.0, -0.1}}, Disc{{0.0, 1.6}, 0.3},
                               Rectangle{{-1.6, -0.1}, {-0.9, 0.5}}};
  config.geometry.object = {{1.25, 0.2}, 0.2};
  config.start_A = {110, 0};
  // Step (tenths), grid rows and columns: 181 x 356 at 1 degree.
  for (const auto& [tenths, rows, cols] :
       {std::tuple{50, 37, 72}, std::tuple{25, 73, 143}, std::tuple{10, 181, 356}}) {
    config.grid_step_tenths = tenths;
    const Arm arm(config);
    const double step = tenths / 10.0;
    ASSERT_EQ(arm.shoulder_steps(), rows) << step;
    ASSERT_EQ(arm.elbow_steps(), cols) << step;
    std::int32_t expected_state = 0;
    for (std::int32_t i = 0; i < rows; ++i) {
      for (std::int32_t j = 0; j < cols; ++j) {
        const ArmPose pose = forward_kinematics(config.geometry, step * i, -180.0 + step * j);
        const bool collides = arm_collides(config.geometry, pose);
        ASSERT_EQ(arm.collides(i, j), collides) << step << ": " << i << ", " << j;
        if (collides) continue;
        const std::int32_t s = arm.state_of(i, j);
        ASSERT_EQ(s, expected_state++);
        ASSERT_EQ(arm.is_goal(s), touches_object(config.geometry, pose));
        ASSERT_EQ(arm.angles_of(s), (JointAngles{step * i, -180.0 + step * j}));
      }
    }
    EXPECT_EQ(arm.num_states(), expected_state);
    EXPECT_EQ(arm.angles_of(arm.start_state_A()), (JointAngles{110.0, 0.0}));
  }
}

TEST(ArmFineGrid, DefaultStepIsThePapersFiveDegrees) {
  EXPECT_EQ(ArmConfig{}.grid_step_tenths, 50);
  ArmConfig explicit_step = small_config();
  explicit_step.grid_step_tenths = 50;
  const Arm by_default(small_config());
  const Arm by_key(explicit_step);
  ASSERT_EQ(by_key.num_states(), by_default.num_states());
  for (std::int32_t s = 0; s < by_default.num_states(); ++s) {
    EXPECT_EQ(by_key.state_vector(s), by_default.state_vector(s));
  }
}

// The field an invalid configuration is blamed on.
ArmConfigField error_field(const ArmConfig& config) {
  try {
    const Arm arm(config);
  } catch (const ArmConfigError& error) {
    return error.field();
  }
  ADD_FAILURE() << "expected an ArmConfigError";
  return ArmConfigField::links;
}

TEST(Arm, RejectsBadConfigurations) {
  ArmConfig config = small_config();
  config.limits.shoulder_max_deg = 22;
  EXPECT_EQ(error_field(config), ArmConfigField::shoulder_limits);
  config = small_config();
  config.limits.elbow_min_deg = 20;
  EXPECT_EQ(error_field(config), ArmConfigField::elbow_limits);
  config = small_config();
  config.limits.elbow_min_deg = -180;
  config.limits.elbow_max_deg = 180;  // -180 and 180 would be one pose twice
  EXPECT_EQ(error_field(config), ArmConfigField::elbow_limits);
  config = small_config();
  config.start_A = {10, 0};  // collides
  EXPECT_EQ(error_field(config), ArmConfigField::start_A);
  config.start_A = {20, 0};  // the goal
  EXPECT_EQ(error_field(config), ArmConfigField::start_A);
  config.start_A = {25, 0};  // past the limit
  EXPECT_EQ(error_field(config), ArmConfigField::start_A);
  config.start_A = {3, 0};  // off the grid
  EXPECT_EQ(error_field(config), ArmConfigField::start_A);
  config.start_A = {2.5, 0};  // off the 5-degree grid, on the 2.5-degree one
  EXPECT_EQ(error_field(config), ArmConfigField::start_A);
  config.grid_step_tenths = 25;
  EXPECT_NO_THROW(Arm{config});
  config = small_config();
  config.grid_step_tenths = 0;
  EXPECT_EQ(error_field(config), ArmConfigField::grid_step);
  config.grid_step_tenths = 30;  // 3 degrees: 20 is no multiple of it
  EXPECT_EQ(error_field(config), ArmConfigField::shoulder_limits);
  config.grid_step_tenths = 7;  // 0.7 degrees: neither is -10
  config.limits.shoulder_max_deg = 21;
  EXPECT_EQ(error_field(config), ArmConfigField::elbow_limits);
  config = small_config();
  config.geometry.object.center.x += 0.1;
  EXPECT_EQ(error_field(config), ArmConfigField::object);
  config = small_config();
  config.geometry.obstacles.push_back(Disc{{0.0, 0.0}, 0.1});  // around the base
  EXPECT_EQ(error_field(config), ArmConfigField::obstacles);
  config = small_config();
  config.geometry.link1_length = -1.0;
  EXPECT_EQ(error_field(config), ArmConfigField::links);
}

TEST(Arm, ActionNames) {
  EXPECT_EQ(action_name(kShoulderPlus), "shoulder+");
  EXPECT_EQ(action_name(kShoulderMinus), "shoulder-");
  EXPECT_EQ(action_name(kElbowPlus), "elbow+");
  EXPECT_EQ(action_name(kElbowMinus), "elbow-");
  EXPECT_THROW(action_name(4), std::out_of_range);
}
}  // namespace
}  // namespace ggk::sims::arm
