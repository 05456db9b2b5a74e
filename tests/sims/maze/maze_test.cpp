#include "sims/maze/maze.hpp"

#include <cmath>
#include <cstdlib>
#include <deque>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace ggk::sims::maze {
namespace {

using kernels::RandomStream;

// The error a map raises, or a failure when it parses.
MazeParseError parse_error_of(const std::string& text) {
  try {
    Maze maze(text);
  } catch (const MazeParseError& error) {
    return error;
  }
  ADD_FAILURE() << "expected a MazeParseError for:\n" << text;
  return MazeParseError(0, 0, "none");
}

TEST(Maze, NumbersFreeCellsRowMajor) {
  const Maze maze(
      "#####\n"
      "#..G#\n"
      "#.#.#\n"
      "#####\n");
  EXPECT_EQ(maze.rows(), 4);
  EXPECT_EQ(maze.cols(), 5);
  ASSERT_EQ(maze.num_states(), 5);
  EXPECT_EQ(maze.state_of(1, 1), 0);
  EXPECT_EQ(maze.state_of(1, 2), 1);
  EXPECT_EQ(maze.state_of(1, 3), 2);
  EXPECT_EQ(maze.state_of(2, 1), 3);
  EXPECT_EQ(maze.state_of(2, 3), 4);
  EXPECT_EQ(maze.state_of(0, 0), kNoState);
  EXPECT_EQ(maze.state_of(2, 2), kNoState);
  EXPECT_EQ(maze.state_of(-1, 1), kNoState);
  EXPECT_EQ(maze.state_of(1, 5), kNoState);
  EXPECT_EQ(maze.cell_of(3), (Cell{2, 1}));
  EXPECT_TRUE(maze.is_goal(2));
  EXPECT_FALSE(maze.is_goal(0));
  EXPECT_EQ(maze.goal_states(), std::vector<std::int32_t>{2});
  EXPECT_EQ(maze.state_vector(4), (std::array<double, 2>{2.0, 3.0}));
  const kernels::RowMatrixXd vectors = maze.state_vectors();
  ASSERT_EQ(vectors.rows(), 5);
  ASSERT_EQ(vectors.cols(), 2);
  for (std::int32_t s = 0; s < maze.num_states(); ++s) {
    EXPECT_EQ(vectors(s, 0), maze.cell_of(s).row);
    EXPECT_EQ(vectors(s, 1), maze.cell_of(s).col);
  }
  EXPECT_THROW(maze.cell_of(5), std::out_of_range);
  EXPECT_THROW(maze.is_goal(-1), std::out_of_range);
}

TEST(Maze, IgnoresBlankLinesTrailingSpacesAndCarriageReturns) {
  const Maze maze("\n  \n#.G#   \r\n#..#\t\r\n\n \n");
  EXPECT_EQ(maze.rows(), 2);
  EXPECT_EQ(maze.cols(), 4);
  EXPECT_EQ(maze.num_states(), 4);
  EXPECT_EQ(maze.to_text(), "#.G#\n#..#\n");
  // No final newline.
  EXPECT_EQ(Maze("G.").num_states(), 2);
}

TEST(Maze, ParseErrorsNameRowAndColumn) {
  // Rows count lines of the text as given, leading blank lines included.
  const MazeParseError unknown = parse_error_of("\n#####\n#.Gx#\n#####\n");
  EXPECT_EQ(unknown.row(), 3);
  EXPECT_EQ(unknown.column(), 4);
  EXPECT_NE(std::string(unknown.what()).find("row 3, column 4"), std::string::npos)
      << unknown.what();
  EXPECT_NE(std::string(unknown.what()).find("'x'"), std::string::npos) << unknown.what();

  const MazeParseError space = parse_error_of("#. G#\n");
  EXPECT_EQ(space.row(), 1);
  EXPECT_EQ(space.column(), 3);

  const MazeParseError shorter = parse_error_of("#####\n#.G#\n#####\n");
  EXPECT_EQ(shorter.row(), 2);
  EXPECT_EQ(shorter.column(), 5);
  EXPECT_NE(std::string(shorter.what()).find("row 2, column 5"), std::string::npos)
      << shorter.what();

  const MazeParseError longer = parse_error_of("####\n#.G##\n####\n");
  EXPECT_EQ(longer.row(), 2);
  EXPECT_EQ(longer.column(), 5);

  const MazeParseError blank_inside = parse_error_of("#.G#\n\n#..#\n");
  EXPECT_EQ(blank_inside.row(), 2);
  EXPECT_EQ(blank_inside.column(), 1);
}

TEST(Maze, RejectsMapsWithoutFreeCellGoalOrCells) {
  EXPECT_NE(std::string(parse_error_of("#G#\n").what()).find("no free cell"), std::string::npos);
  EXPECT_NE(std::string(parse_error_of("#..#\n").what()).find("no goal"), std::string::npos);
  EXPECT_NE(std::string(parse_error_of(" \n\n").what()).find("empty"), std::string::npos);
  EXPECT_NE(std::string(parse_error_of("").what()).find("empty"), std::string::npos);
}

TEST(Maze, ActionNames) {
  EXPECT_EQ(action_name(kUp), "up");
  EXPECT_EQ(action_name(kDown), "down");
  EXPECT_EQ(action_name(kLeft), "left");
  EXPECT_EQ(action_name(kRight), "right");
  EXPECT_THROW(action_name(4), std::out_of_range);
  EXPECT_THROW(action_name(-1), std::out_of_range);
}

TEST(Maze, MovesOneCellInEachDirection) {
  const Maze maze(
      "G...\n"
      "....\n"
      "....\n");
  const std::int32_t centre = maze.state_of(1, 1);
  EXPECT_EQ(maze.cell_of(maze.move(centre, kUp)), (Cell{0, 1}));
  EXPECT_EQ(maze.cell_of(maze.move(centre, kDown)), (Cell{2, 1}));
  EXPECT_EQ(maze.cell_of(maze.move(centre, kLeft)), (Cell{1, 0}));
  EXPECT_EQ(maze.cell_of(maze.move(centre, kRight)), (Cell{1, 2}));
}

TEST(Maze, WallsBlock) {
  const Maze maze(
      "#####\n"
      "#.#G#\n"
      "##..#\n"
      "#####\n");
  RandomStream random(1, 0, 0);
  const std::int32_t s = maze.state_of(1, 1);  // walled in on all four sides
  for (std::int32_t a = 0; a < kNumActions; ++a) {
    const StepResult result = maze.step(s, a, random, 0.0);
    EXPECT_EQ(result.next_state, s) << action_name(a);
    EXPECT_EQ(result.reward, 0.0);
    EXPECT_FALSE(result.terminal);
  }
  const std::int32_t below_goal = maze.state_of(2, 3);
  EXPECT_EQ(maze.move(below_goal, kRight), below_goal);
  EXPECT_EQ(maze.move(below_goal, kDown), below_goal);
  EXPECT_EQ(maze.cell_of(maze.move(below_goal, kLeft)), (Cell{2, 2}));
}

TEST(Maze, GridBordersBlock) {
  const Maze maze(
      ".G\n"
      "..\n");
  RandomStream random(1, 0, 0);
  const std::int32_t top_left = maze.state_of(0, 0);
  const std::int32_t bottom_right = maze.state_of(1, 1);
  EXPECT_EQ(maze.step(top_left, kUp, random, 0.0).next_state, top_left);
  EXPECT_EQ(maze.step(top_left, kLeft, random, 0.0).next_state, top_left);
  EXPECT_EQ(maze.step(bottom_right, kDown, random, 0.0).next_state, bottom_right);
  EXPECT_EQ(maze.step(bottom_right, kRight, random, 0.0).next_state, bottom_right);
}

TEST(Maze, GoalRewardAndTerminal) {
  const Maze maze("..GG\n");
  RandomStream random(1, 0, 0);
  const StepResult enter = maze.step(maze.state_of(0, 1), kRight, random, 0.0);
  EXPECT_EQ(enter.next_state, maze.state_of(0, 2));
  EXPECT_EQ(enter.reward, 1.0);
  EXPECT_TRUE(enter.terminal);

  // From a goal into another goal (or staying at one): terminal, but no reward.
  const StepResult within = maze.step(maze.state_of(0, 2), kRight, random, 0.0);
  EXPECT_EQ(within.next_state, maze.state_of(0, 3));
  EXPECT_EQ(within.reward, 0.0);
  EXPECT_TRUE(within.terminal);
  const StepResult stay = maze.step(maze.state_of(0, 3), kRight, random, 0.0);
  EXPECT_EQ(stay.reward, 0.0);
  EXPECT_TRUE(stay.terminal);

  const StepResult leave = maze.step(maze.state_of(0, 2), kLeft, random, 0.0);
  EXPECT_EQ(leave.next_state, maze.state_of(0, 1));
  EXPECT_EQ(leave.reward, 0.0);
  EXPECT_FALSE(leave.terminal);

  const StepResult plain = maze.step(maze.state_of(0, 0), kLeft, random, 0.0);
  EXPECT_EQ(plain.reward, 0.0);
  EXPECT_FALSE(plain.terminal);
}

TEST(Maze, SlipSendsAnotherDirectionUniformly) {
  const Maze maze(
      "G..\n"
      "...\n"
      "...\n");
  const std::int32_t centre = maze.state_of(1, 1);
  std::array<std::int32_t, kNumActions> reached{};  // state reached by each direction
  for (std::int32_t a = 0; a < kNumActions; ++a) reached[a] = maze.move(centre, a);

  constexpr int kSteps = 20000;
  constexpr double kSlip = 0.3;
  for (std::int32_t intended = 0; intended < kNumActions; ++intended) {
    RandomStream random(2024, 7, static_cast<std::uint32_t>(intended));
    std::array<int, kNumActions> counts{};
    for (int i = 0; i < kSteps; ++i) {
      const std::int32_t next = maze.step(centre, intended, random, kSlip).next_state;
      int direction = -1;
      for (std::int32_t a = 0; a < kNumActions; ++a) {
        if (reached[a] == next) direction = a;
      }
      ASSERT_GE(direction, 0);
      ++counts[direction];
    }
    // Binomial proportions within 4 standard errors (a false alarm about 1 in 16,000).
    const double slipped = 1.0 - static_cast<double>(counts[intended]) / kSteps;
    const double slip_se = std::sqrt(kSlip * (1.0 - kSlip) / kSteps);
    EXPECT_NEAR(slipped, kSlip, 4.0 * slip_se) << action_name(intended);
    const double other_p = kSlip / 3.0;
    const double other_se = std::sqrt(other_p * (1.0 - other_p) / kSteps);
    for (std::int32_t a = 0; a < kNumActions; ++a) {
      if (a == intended) continue;
      EXPECT_NEAR(static_cast<double>(counts[a]) / kSteps, other_p, 4.0 * other_se)
          << "intended " << action_name(intended) << ", went " << action_name(a);
    }
  }
}

TEST(Maze, ZeroSlipDrawsNoRandomNumber) {
  const Maze maze("G..\n...\n");
  RandomStream random(5, 1, 2);
  RandomStream untouched = random;
  for (std::int32_t a = 0; a < kNumActions; ++a) maze.step(maze.state_of(1, 1), a, random, 0.0);
  EXPECT_EQ(random.next_u64(), untouched.next_u64());
}

TEST(Maze, FixedStreamGivesFixedTrajectory) {
  const Maze maze(
      "#######\n"
      "#.....#\n"
      "#.#.#.#\n"
      "#....G#\n"
      "#######\n");
  const auto trajectory = [&maze](std::uint32_t purpose) {
    RandomStream random(99, 3, purpose);
    std::vector<std::int32_t> states;
    std::int32_t s = 0;
    for (int i = 0; i < 2000; ++i) {
      const auto action = static_cast<std::int32_t>(random.uniform_index(kNumActions));
      const StepResult result = maze.step(s, action, random, 0.2);
      states.push_back(result.next_state);
      s = result.terminal ? 0 : result.next_state;
    }
    return states;
  };
  EXPECT_EQ(trajectory(1), trajectory(1));
  EXPECT_NE(trajectory(1), trajectory(2));
}

TEST(Maze, StepRejectsBadArguments) {
  const Maze maze("G.\n");
  RandomStream random(1, 0, 0);
  EXPECT_THROW(maze.step(0, 4, random, 0.0), std::out_of_range);
  EXPECT_THROW(maze.step(0, -1, random, 0.0), std::out_of_range);
  EXPECT_THROW(maze.step(2, 0, random, 0.0), std::out_of_range);
  EXPECT_THROW(maze.step(0, 0, random, -0.1), std::invalid_argument);
  EXPECT_THROW(maze.step(0, 0, random, 1.5), std::invalid_argument);
  EXPECT_THROW(maze.step(0, 0, random, std::nan("")), std::invalid_argument);
}

// The map shipped with the job files: four rooms joined by doorways, every free
// cell connected to the goal.
TEST(Maze, ShippedFourRoomsMapIsConnected) {
  const char* source_dir = std::getenv("GGK_SOURCE_DIR");
  if (source_dir == nullptr) GTEST_SKIP() << "GGK_SOURCE_DIR is not set (run through ctest)";
  std::ifstream file(std::string(source_dir) + "/jobs/maps/four-rooms.txt");
  ASSERT_TRUE(file) << "cannot open jobs/maps/four-rooms.txt";
  std::stringstream text;
  text << file.rdbuf();
  const Maze maze(text.str());
  EXPECT_EQ(maze.num_states(), 404);
  EXPECT_EQ(maze.goal_states().size(), 4u);

  std::vector<bool> seen(static_cast<std::size_t>(maze.num_states()), false);
  std::deque<std::int32_t> queue(maze.goal_states().begin(), maze.goal_states().end());
  for (const std::int32_t g : queue) seen[static_cast<std::size_t>(g)] = true;
  while (!queue.empty()) {
    const std::int32_t s = queue.front();
    queue.pop_front();
    for (std::int32_t a = 0; a < kNumActions; ++a) {
      const std::int32_t next = maze.move(s, a);
      if (!seen[static_cast<std::size_t>(next)]) {
        seen[static_cast<std::size_t>(next)] = true;
        queue.push_back(next);
      }
    }
  }
  for (std::int32_t s = 0; s < maze.num_states(); ++s) {
    EXPECT_TRUE(seen[static_cast<std::size_t>(s)]) << "state " << s << " cannot reach the goal";
  }
}

}  // namespace
}  // namespace ggk::sims::maze
