// The [maze] table refuses maps on which no fit can succeed: a goal walled off
// from every free cell.

#include "engine/tasks/maze/maze_table.hpp"

#include <string>

#include <gtest/gtest.h>

#include "engine/job/job_file.hpp"
#include "engine/tasks/task_list.hpp"

namespace ggk::engine {
namespace {

// The JobError message of a job with the inline map `map`, or "ok".
std::string map_outcome(const std::string& map) {
  const std::string text =
      "name = \"m\"\ntask = \"maze\"\nruns = 1\nseed = 0\n[sweep]\nkernels = [4]\n"
      "sigma = [2.0]\n[maze]\nmap = \"\"\"\n" +
      map + "\"\"\"\n";
  JobLoadOptions options;
  options.check_output = false;
  try {
    parse_job(text, "jobs/walled.toml", task_tables(), options);
  } catch (const JobError& error) {
    return error.what();
  }
  return "ok";
}

TEST(MazeTable, AGoalWalledOffFromEveryFreeCellIsRefused) {
  const std::string message = map_outcome(
      "#######\n"
      "#...#G#\n"
      "#...###\n"
      "#######\n");
  EXPECT_NE(message.find("jobs/walled.toml:9:1: [maze] map: no free cell '.' can reach a goal"),
            std::string::npos)
      << message;
  EXPECT_NE(message.find("success 0"), std::string::npos) << message;
  // Goals next to each other, all walled off together.
  EXPECT_NE(map_outcome("#####\n#GG##\n###.#\n#####\n").find("no free cell"), std::string::npos);
}

TEST(MazeTable, AGoalSomeFreeCellReachesIsAccepted) {
  // One room walled off from the goal, the other not.
  EXPECT_EQ(map_outcome("#######\n#.#..G#\n#######\n"), "ok");
  // A goal reached only through another goal.
  EXPECT_EQ(map_outcome("#####\n#.GG#\n#####\n"), "ok");
}

// Greedy tests bounded by what a person would run (jobs/README.md): 2^31 - 1
// steps from every start is a job that never ends.
TEST(MazeTable, TestMaxStepsIsBounded) {
  const auto with_steps = [](const std::string& steps) {
    const std::string text =
        "name = \"m\"\ntask = \"maze\"\nruns = 1\nseed = 0\n[sweep]\nkernels = [4]\n"
        "sigma = [2.0]\n[maze]\ntest_max_steps = " +
        steps + "\nmap = \"G..\"\n";
    JobLoadOptions options;
    options.check_output = false;
    try {
      return std::to_string(task_config_as<sims::maze::MazeConfig>(
                                parse_job(text, "jobs/steps.toml", task_tables(), options))
                                .test_max_steps);
    } catch (const JobError& error) {
      return std::string(error.what());
    }
  };
  EXPECT_EQ(with_steps("1000000"), "1000000");
  const std::string message = with_steps("2147483647");
  EXPECT_NE(message.find("jobs/steps.toml:9:1: [maze] test_max_steps: expected an integer in [1, "
                         "1000000], got 2147483647"),
            std::string::npos)
      << message;
  EXPECT_NE(with_steps("1000001").find("got 1000001"), std::string::npos);
}

}  // namespace
}  // namespace ggk::engine
