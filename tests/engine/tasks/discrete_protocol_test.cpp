// nearest_visited_states: the k-d tree search gives exactly what the scan it
// replaced gave (the reference below, kept verbatim): the same nearest state,
// ties included, and bit-identical distances. And a 500 x 500 maze runs (its
// cost against states is measured in bench/cost_growth_benchmark.cpp,
// BM_MazeRun; no timing assertion here).

#include "engine/tasks/discrete_protocol.hpp"

#include <cstdint>
#include <limits>
#include <random>
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

// The scan over every visited state for every unvisited one (the code before
// the k-d tree, O(n^2)).
void brute_force_nearest(const kernels::RowMatrixXd& vectors,
                         const std::vector<std::uint8_t>& visited,
                         std::vector<std::int32_t>& nearest, std::vector<double>& distance) {
  const auto n = static_cast<std::int32_t>(vectors.rows());
  nearest.assign(static_cast<std::size_t>(n), 0);
  distance.assign(static_cast<std::size_t>(n), 0.0);
  for (std::int32_t s = 0; s < n; ++s) {
    if (visited[static_cast<std::size_t>(s)]) {
      nearest[static_cast<std::size_t>(s)] = s;
      continue;
    }
    double best = std::numeric_limits<double>::infinity();
    for (std::int32_t v = 0; v < n; ++v) {
      if (!visited[static_cast<std::size_t>(v)]) continue;
      const double d = (vectors.row(s) - vectors.row(v)).norm();
      if (d < best) {
        best = d;
        nearest[static_cast<std::size_t>(s)] = v;
      }
    }
    distance[static_cast<std::size_t>(s)] = best;
  }
}

void expect_same_as_brute_force(const kernels::RowMatrixXd& vectors,
                                const std::vector<std::uint8_t>& visited, const std::string& what) {
  std::vector<std::int32_t> nearest, expected_nearest;
  std::vector<double> distance, expected_distance;
  nearest_visited_states(vectors, visited, nearest, distance);
  brute_force_nearest(vectors, visited, expected_nearest, expected_distance);
  ASSERT_EQ(nearest.size(), expected_nearest.size()) << what;
  for (std::size_t s = 0; s < nearest.size(); ++s) {
    ASSERT_EQ(nearest[s], expected_nearest[s]) << what << ", state " << s;
    // Bit-identical, infinities included.
    ASSERT_EQ(distance[s], expected_distance[s]) << what << ", state " << s;
  }
}

// A random maze map of rows x cols with walls of density `walls` and one goal.
std::string random_map(std::mt19937& random, int rows, int cols, double walls) {
  std::bernoulli_distribution wall(walls);
  std::string map;
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) map += r == 0 && c == 0 ? 'G' : (wall(random) ? '#' : '.');
    map += '\n';
  }
  map[static_cast<std::size_t>(cols + 2)] = '.';  // (1, 1): a free cell
  return map;
}

std::vector<std::uint8_t> random_visited(std::mt19937& random, std::int64_t n, double density) {
  std::bernoulli_distribution visit(density);
  std::vector<std::uint8_t> visited(static_cast<std::size_t>(n));
  for (auto& v : visited) v = visit(random) ? 1 : 0;
  return visited;
}

TEST(NearestVisitedStates, EqualsTheScanOnRandomMazes) {
  std::mt19937 random(20240601);
  std::uniform_int_distribution<int> size(2, 40);
  for (int trial = 0; trial < 200; ++trial) {
    const sims::maze::Maze maze(random_map(random, size(random), size(random), 0.3));
    const kernels::RowMatrixXd vectors = maze.state_vectors();
    // From one visited state in a hundred to all of them: grid distances tie often.
    for (const double density : {0.01, 0.05, 0.3, 0.9, 1.0}) {
      expect_same_as_brute_force(vectors, random_visited(random, vectors.rows(), density),
                                 "trial " + std::to_string(trial));
    }
  }
}

TEST(NearestVisitedStates, EqualsTheScanOnPointsWithTiesAndDuplicates) {
  std::mt19937 random(7);
  for (const int dims : {1, 2, 3, 5}) {
    for (int trial = 0; trial < 50; ++trial) {
      const int n = 1 + trial * 7;
      kernels::RowMatrixXd vectors(n, dims);
      // Coarse lattice coordinates (many exact ties and duplicate points), and
      // some irrational-looking ones.
      std::uniform_int_distribution<int> lattice(-3, 3);
      std::uniform_real_distribution<double> real(-10.0, 10.0);
      for (int i = 0; i < n; ++i) {
        for (int k = 0; k < dims; ++k) {
          vectors(i, k) = trial % 3 == 0 ? real(random) : 0.5 * lattice(random);
        }
      }
      expect_same_as_brute_force(vectors, random_visited(random, n, 0.2),
                                 std::to_string(dims) + "-d trial " + std::to_string(trial));
    }
  }
}

TEST(NearestVisitedStates, NoVisitedStateGivesStateZeroAtInfiniteDistance) {
  kernels::RowMatrixXd vectors(3, 2);
  vectors << 0, 0, 1, 0, 2, 0;
  expect_same_as_brute_force(vectors, {0, 0, 0}, "nothing visited");
  expect_same_as_brute_force(vectors, {0, 1, 0}, "one visited");
}

// A 500 x 500 open room (about 250,000 states) with about 10,000 visited: the
// scan took about a minute here, the k-d tree a fraction of a second.
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
