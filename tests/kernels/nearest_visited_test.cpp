// nearest_visited_states (kernels/nearest_visited.hpp): the k-d tree search
// gives exactly what a scan over the visited states in id order gives: the same
// nearest state, ties included, and bit-identical distances.

#include "kernels/nearest_visited.hpp"

#include <cstdint>
#include <limits>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

namespace ggk::kernels {
namespace {

// The reference: a scan over every visited state for every unvisited one, O(n^2).
void brute_force_nearest(const RowMatrixXd& vectors, const std::vector<std::uint8_t>& visited,
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

void expect_same_as_brute_force(const RowMatrixXd& vectors,
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

// The free cells of a random rows x cols grid with walls of density `walls`, as
// (row, col) vectors in row-major order (a maze's state vectors); at least one.
RowMatrixXd random_free_cells(std::mt19937& random, int rows, int cols, double walls) {
  std::bernoulli_distribution wall(walls);
  std::vector<std::pair<int, int>> cells;
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      if (!wall(random) || (r == 0 && c == 0)) cells.emplace_back(r, c);
    }
  }
  RowMatrixXd vectors(static_cast<Eigen::Index>(cells.size()), 2);
  for (std::size_t i = 0; i < cells.size(); ++i) {
    vectors(static_cast<Eigen::Index>(i), 0) = cells[i].first;
    vectors(static_cast<Eigen::Index>(i), 1) = cells[i].second;
  }
  return vectors;
}

std::vector<std::uint8_t> random_visited(std::mt19937& random, std::int64_t n, double density) {
  std::bernoulli_distribution visit(density);
  std::vector<std::uint8_t> visited(static_cast<std::size_t>(n));
  for (auto& v : visited) v = visit(random) ? 1 : 0;
  return visited;
}

TEST(NearestVisitedStates, EqualsTheScanOnRandomGrids) {
  std::mt19937 random(20240601);
  std::uniform_int_distribution<int> size(2, 40);
  for (int trial = 0; trial < 200; ++trial) {
    const RowMatrixXd vectors = random_free_cells(random, size(random), size(random), 0.3);
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
      RowMatrixXd vectors(n, dims);
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
  RowMatrixXd vectors(3, 2);
  vectors << 0, 0, 1, 0, 2, 0;
  expect_same_as_brute_force(vectors, {0, 0, 0}, "nothing visited");
  expect_same_as_brute_force(vectors, {0, 1, 0}, "one visited");
}

}  // namespace
}  // namespace ggk::kernels
