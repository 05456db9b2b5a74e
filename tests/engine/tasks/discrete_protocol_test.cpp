// The discrete protocol on a large map: a 500 x 500 maze runs (its cost against
// states is measured in bench/cost_growth_benchmark.cpp, BM_MazeRun; no timing
// assertion here). Its test and metrics on real tasks: the maze, arm and chain
// task tests; the nearest visited states: tests/kernels/nearest_visited_test.cpp.

#include "engine/tasks/discrete_protocol.hpp"

#include <cstdint>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "engine/job/job_file.hpp"
#include "engine/job/sweep.hpp"
#include "engine/tasks/maze/maze_task.hpp"
#include "engine/tasks/task_list.hpp"
#include "sims/maze/maze.hpp"

namespace ggk::engine {
namespace {

// A 500 x 500 open room (about 250,000 states) with about 10,000 visited.
TEST(MazeProtocol, ALargeMapRuns) {
  const int side = 500;
  std::string map(static_cast<std::size_t>(side) * (side + 1), '.');
  for (int r = 0; r < side; ++r) {
    map[static_cast<std::size_t>(r) * (side + 1) + side] = '\n';
  }
  map[0] = 'G';
  const std::string text =
      "name = \"large\"\ntask = \"maze\"\nruns = 1\nseed = 3\n"
      "[sweep]\nbasis = [\"ggk\"]\nkernels = [4]\nsigma = [10.0]\n"
      "[maze]\nseries = 20\nsteps_per_series = 1000\ntest_max_steps = 1\nmap = \"\"\"\n" +
      map + "\"\"\"\n";
  JobLoadOptions options;
  options.check_output = false;
  const JobSpec job = parse_job(text, "large.toml", task_tables(), options);
  const std::vector<SweepPoint> points = expand_sweep(job);
  const RunRecord record = run_maze(task_config_as<sims::maze::MazeConfig>(job), job, 0, points);
  ASSERT_EQ(record.fits.size(), 1U);
  EXPECT_TRUE(record.fits[0].status == "converged" || record.fits[0].status == "max_iterations")
      << record.fits[0].status << ": " << record.fits[0].message;
  EXPECT_EQ(record.node_states.rows(), side * side);
}

}  // namespace
}  // namespace ggk::engine
