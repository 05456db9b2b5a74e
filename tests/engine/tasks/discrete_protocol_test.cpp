// The discrete protocol on a large map: a 500 x 500 maze runs (its cost against
// states is measured in bench/cost_growth_benchmark.cpp, BM_MazeRun; no timing
// assertion here); a non-finite state vector stops the run. Its test and metrics on real tasks: the
// maze, arm and chain task tests; the nearest visited states:
// tests/kernels/nearest_visited_test.cpp.

#include "engine/tasks/discrete_protocol.hpp"

#include <algorithm>
#include <cstdint>
#include <limits>
#include <stdexcept>
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

// A state vector with a NaN once became zero kernel values (a plausible fit on a
// wrong basis); now the run stops with an error naming the run, the fit and the
// state. A line of 6 states, right-moves reach the goal at 5, and a state 6 that
// no walk visits (a visited one's NaN is refused by the graph's edge weights).
TEST(DiscreteProtocol, ANonFiniteStateVectorStopsTheRunNamingFitAndState) {
  DiscreteEnvironment env;
  env.num_states = 7;
  env.num_actions = 2;
  env.action_names = {"left", "right"};
  env.state_vectors.resize(7, 1);
  for (std::int32_t s = 0; s < 7; ++s) env.state_vectors(s, 0) = s;
  env.goal_states = {5};
  env.start_states = {0, 1, 2, 3, 4};
  env.step = [](std::int32_t state, std::int32_t action, kernels::RandomStream&) {
    const std::int32_t next = state == 6 ? 6 : std::clamp(state + (action == 1 ? 1 : -1), 0, 5);
    return Transition{next, next == 5 ? 1.0 : 0.0, next == 5};
  };
  JobSpec job;
  job.task = "line";
  job.sweep.basis = {KernelType::ogk};
  job.sweep.kernels = {2};
  job.sweep.sigma = {1.0};
  job.sweep.solver = {kernels::LspiSolver::brm};
  job.sweep.lambda = {1e-6};
  const std::vector<SweepPoint> points = expand_sweep(job);
  const DiscreteProtocol protocol{4, 20, 10, false};
  const RunRecord sound = run_discrete_protocol(env, protocol, job, 0, points);
  ASSERT_EQ(sound.fits.size(), 1U);
  EXPECT_NE(sound.fits[0].status, "invalid") << sound.fits[0].message;

  env.state_vectors(6, 0) = std::numeric_limits<double>::quiet_NaN();
  try {
    run_discrete_protocol(env, protocol, job, 0, points);
    ADD_FAILURE() << "a NaN state vector gave a fit";
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("run 0, fit ogk with 2 kernels, sigma 1: "), std::string::npos) << what;
    EXPECT_NE(what.find("state 6 is not finite: coordinate 0 is nan"), std::string::npos) << what;
  }
}

}  // namespace
}  // namespace ggk::engine
