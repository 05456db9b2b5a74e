#include "kernels/shortest_paths.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <numeric>
#include <queue>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include "kernels/random_stream.hpp"

namespace ggk::kernels {
namespace {

// A random graph: a spanning path when `connected`, plus random extra edges.
// Without `connected`, nodes split into two halves with no edge between them.
CsrGraph random_graph(std::int32_t n, std::int32_t extra_edges, bool connected,
                      std::uint64_t seed) {
  RandomStream rng(seed, 0, 0);
  std::vector<WeightedEdge> edges;
  const std::int32_t half = n / 2;
  auto same_part = [&](std::int32_t u, std::int32_t v) {
    return connected || (u < half) == (v < half);
  };
  for (std::int32_t u = 0; u + 1 < n; ++u) {
    if (same_part(u, u + 1)) edges.push_back({u, u + 1, rng.uniform(0.1, 10.0)});
  }
  for (std::int32_t e = 0; e < extra_edges; ++e) {
    const auto u = static_cast<std::int32_t>(rng.uniform_index(n));
    const auto v = static_cast<std::int32_t>(rng.uniform_index(n));
    if (same_part(u, v)) edges.push_back({u, v, rng.uniform(0.1, 10.0)});
  }
  return graph_from_edges(n, edges);
}

RowMatrixXd floyd_warshall(const CsrGraph& g) {
  RowMatrixXd d = RowMatrixXd::Constant(g.num_nodes, g.num_nodes, kUnreachable);
  for (std::int32_t u = 0; u < g.num_nodes; ++u) {
    d(u, u) = 0.0;
    for (std::int64_t arc = g.indptr[u]; arc < g.indptr[u + 1]; ++arc) {
      d(u, g.indices[arc]) = std::min(d(u, g.indices[arc]), g.weights[arc]);
    }
  }
  for (std::int32_t k = 0; k < g.num_nodes; ++k)
    for (std::int32_t i = 0; i < g.num_nodes; ++i)
      for (std::int32_t j = 0; j < g.num_nodes; ++j) d(i, j) = std::min(d(i, j), d(i, k) + d(k, j));
  return d;
}

// Textbook Dijkstra with a binary heap (std::priority_queue, lazy deletion), the
// reference for bit-for-bit equality: d(v) = d(u) + w(u, v) in the order nodes settle.
std::vector<double> binary_heap_dijkstra(const CsrGraph& g, std::int32_t source) {
  std::vector<double> d(static_cast<std::size_t>(g.num_nodes), kUnreachable);
  std::vector<char> settled(static_cast<std::size_t>(g.num_nodes), 0);
  using Item = std::pair<double, std::int32_t>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> heap;
  d[source] = 0.0;
  heap.push({0.0, source});
  while (!heap.empty()) {
    const auto [du, u] = heap.top();
    heap.pop();
    if (settled[u]) continue;
    settled[u] = 1;
    for (std::int64_t arc = g.indptr[u]; arc < g.indptr[u + 1]; ++arc) {
      const std::int32_t v = g.indices[arc];
      const double candidate = du + g.weights[arc];
      if (candidate < d[v]) {
        d[v] = candidate;
        heap.push({candidate, v});
      }
    }
  }
  return d;
}

// Rows x cols grid, 8 neighbours: axis steps of `step`, diagonals of step * sqrt(2)
// (a joint grid whose edge weights are state distances), so equal-length paths
// abound and sum to different doubles depending on the order of their steps.
CsrGraph joint_grid(std::int32_t rows, std::int32_t cols, double step) {
  std::vector<WeightedEdge> edges;
  const double diagonal = std::hypot(step, step);
  for (std::int32_t r = 0; r < rows; ++r) {
    for (std::int32_t c = 0; c < cols; ++c) {
      const std::int32_t u = r * cols + c;
      if (c + 1 < cols) edges.push_back({u, u + 1, step});
      if (r + 1 < rows) edges.push_back({u, u + cols, step});
      if (r + 1 < rows && c + 1 < cols) edges.push_back({u, u + cols + 1, diagonal});
      if (r + 1 < rows && c > 0) edges.push_back({u, u + cols - 1, diagonal});
    }
  }
  return graph_from_edges(rows * cols, edges);
}

// Random edges whose weights come from a few decimals that doubles cannot hold
// exactly, plus zero weights, weights absorbed by rounding (1e-300) and weights
// that overflow a sum to +infinity.
CsrGraph few_weights_graph(std::int32_t n, std::int32_t edges_per_node, GraphDirection direction,
                           std::uint64_t seed) {
  const double choices[] = {0.1, 0.2, 0.3, 0.7, 1.1, 0.0, 1e-300, 1e308};
  RandomStream rng(seed, 0, 0);
  std::vector<WeightedEdge> edges;
  for (std::int32_t e = 0; e < n * edges_per_node; ++e) {
    const auto u = static_cast<std::int32_t>(rng.uniform_index(n));
    const auto v = static_cast<std::int32_t>(rng.uniform_index(n));
    // Mostly the five decimals; the special weights on about one edge in 16.
    const auto pick = rng.uniform_index(16);
    const double w = pick < 5 ? choices[pick] : pick < 13 ? choices[pick % 5] : choices[pick - 8];
    edges.push_back({u, v, w});
  }
  return graph_from_edges(n, edges, direction);
}

void expect_bits_equal_binary_heap(const CsrGraph& g, std::span<const std::int32_t> sources,
                                   const char* what) {
  const RowMatrixXd actual = geodesic_distances(g, sources);
  for (std::size_t i = 0; i < sources.size(); ++i) {
    const std::vector<double> expected = binary_heap_dijkstra(g, sources[i]);
    ASSERT_EQ(0, std::memcmp(expected.data(), actual.row(static_cast<Eigen::Index>(i)).data(),
                             sizeof(double) * expected.size()))
        << what << ", source " << sources[i];
  }
}

TEST(ShortestPaths, BitIdenticalToBinaryHeapDijkstraOnJointGrids) {
  for (double step : {1.0, 0.08726646259971647 /* 5 degrees in radians */, 0.1}) {
    const CsrGraph g = joint_grid(37, 72, step);
    const std::vector<std::int32_t> sources = {0, 1, 700, 1331, 2663};
    expect_bits_equal_binary_heap(g, sources, "joint grid");
    // The grid really has ties whose sums differ in the last bits: summing the
    // same shortest lengths in another order (Floyd-Warshall's d(i,k) + d(k,j)
    // through the middle node) does not give the same doubles everywhere.
    if (step != 1.0) {
      const std::vector<double> from_corner = binary_heap_dijkstra(g, 0);
      const std::vector<double> from_middle = binary_heap_dijkstra(g, 1331);
      int differing = 0;
      for (std::int32_t v = 0; v < g.num_nodes; ++v) {
        const double through = from_corner[1331] + from_middle[v];
        if (std::abs(through - from_corner[v]) < 1e-9 && through != from_corner[v]) ++differing;
      }
      EXPECT_GT(differing, 0) << "step " << step;
    }
  }
}

TEST(ShortestPaths, BitIdenticalToBinaryHeapDijkstraWithFewDistinctWeights) {
  for (std::uint64_t seed = 1; seed <= 4; ++seed) {
    for (GraphDirection direction : {GraphDirection::undirected, GraphDirection::directed}) {
      const CsrGraph g = few_weights_graph(1500, 3, direction, seed);
      std::vector<std::int32_t> sources;
      for (std::int32_t s = 0; s < g.num_nodes; s += 97) sources.push_back(s);
      expect_bits_equal_binary_heap(g, sources, "few distinct weights");
    }
  }
  // Random real weights, the Khepera SOM graph's kind.
  const CsrGraph g = random_graph(3000, 12000, true, 7);
  const std::vector<std::int32_t> sources = {0, 1234, 2999};
  expect_bits_equal_binary_heap(g, sources, "random weights");
}

class ShortestPathsAgainstFloydWarshall : public testing::TestWithParam<bool> {};

TEST_P(ShortestPathsAgainstFloydWarshall, AllSourcesMatch) {
  const bool connected = GetParam();
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    const CsrGraph g = random_graph(60, 150, connected, seed);
    const RowMatrixXd expected = floyd_warshall(g);
    std::vector<std::int32_t> sources(static_cast<std::size_t>(g.num_nodes));
    std::iota(sources.begin(), sources.end(), 0);
    const RowMatrixXd actual = geodesic_distances(g, sources);
    for (std::int32_t i = 0; i < g.num_nodes; ++i) {
      for (std::int32_t j = 0; j < g.num_nodes; ++j) {
        if (std::isinf(expected(i, j))) {
          EXPECT_TRUE(std::isinf(actual(i, j))) << i << " -> " << j;
        } else {
          EXPECT_NEAR(actual(i, j), expected(i, j), 1e-9 * (1 + expected(i, j)))
              << i << " -> " << j;
        }
      }
    }
    if (!connected) {
      EXPECT_TRUE(std::isinf(actual(0, g.num_nodes - 1)));
    }
  }
}

INSTANTIATE_TEST_SUITE_P(ConnectedAndDisconnected, ShortestPathsAgainstFloydWarshall,
                         testing::Values(true, false),
                         [](const testing::TestParamInfo<bool>& param) {
                           return std::string(param.param ? "connected" : "disconnected");
                         });

TEST(ShortestPaths, BitIdenticalAcrossThreadCounts) {
  const CsrGraph g = random_graph(2000, 6000, true, 11);
  std::vector<std::int32_t> sources;
  for (std::int32_t s = 0; s < g.num_nodes; s += 17) sources.push_back(s);
  // Lift oneTBB's default worker limit (cores - 1) so the arenas really get their threads.
  tbb::global_control allow(tbb::global_control::max_allowed_parallelism, 8);
  auto run_with = [&](int threads) {
    tbb::task_arena arena(threads);
    RowMatrixXd d;
    arena.execute([&] { d = geodesic_distances(g, sources); });
    return d;
  };
  const RowMatrixXd one = run_with(1);
  for (int threads : {2, 4, 8}) {
    const RowMatrixXd many = run_with(threads);
    ASSERT_EQ(0, std::memcmp(one.data(), many.data(), sizeof(double) * one.size()))
        << threads << " threads";
  }
}

TEST(ShortestPaths, LargeResultEqualsRowByRowRuns) {
  // 24 x 22,500 doubles (4.3 MB): geodesic_distances asks for huge pages for a
  // result this size; the rows must still be exactly the single-source runs.
  const CsrGraph g = joint_grid(150, 150, 0.1);
  std::vector<std::int32_t> sources;
  for (std::int32_t s = 0; s < g.num_nodes; s += 938) sources.push_back(s);
  const RowMatrixXd all = geodesic_distances(g, sources);
  ASSERT_EQ(all.rows(), static_cast<Eigen::Index>(sources.size()));
  DijkstraWorkspace workspace;
  std::vector<double> row(static_cast<std::size_t>(g.num_nodes));
  for (std::size_t i = 0; i < sources.size(); ++i) {
    shortest_path_distances(g, sources[i], row, workspace);
    ASSERT_EQ(0, std::memcmp(row.data(), all.row(static_cast<Eigen::Index>(i)).data(),
                             sizeof(double) * row.size()))
        << "source " << sources[i];
  }
}

TEST(ShortestPaths, WorkspaceIsReusableAcrossGraphsOfDifferentSize) {
  DijkstraWorkspace workspace;
  const CsrGraph big = random_graph(100, 300, true, 3);
  const CsrGraph small = random_graph(10, 20, true, 4);
  std::vector<double> d_big(100), d_small(10);
  shortest_path_distances(big, 5, d_big, workspace);
  shortest_path_distances(small, 2, d_small, workspace);
  const RowMatrixXd expected = floyd_warshall(small);
  for (int j = 0; j < 10; ++j) EXPECT_NEAR(d_small[j], expected(2, j), 1e-12);
}

TEST(ShortestPaths, RejectsBadSourcesAndBuffers) {
  const CsrGraph g = random_graph(10, 10, true, 5);
  const std::vector<std::int32_t> bad = {0, 10};
  EXPECT_THROW(geodesic_distances(g, bad), std::invalid_argument);
  DijkstraWorkspace workspace;
  std::vector<double> wrong_size(9);
  EXPECT_THROW(shortest_path_distances(g, 0, wrong_size, workspace), std::invalid_argument);
}

}  // namespace
}  // namespace ggk::kernels
