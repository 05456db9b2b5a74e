#include "kernels/laplacian_eigensolver.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <tuple>
#include <vector>

#include <gtest/gtest.h>

#include "kernels/graph_laplacian.hpp"
#include "kernels/random_stream.hpp"

namespace ggk::kernels {
namespace {

GraphLaplacian unit_laplacian(const CsrGraph& graph, LaplacianKind kind) {
  const std::vector<std::uint8_t> all(static_cast<std::size_t>(graph.num_nodes), 1);
  return graph_laplacian(graph, all, kind, EdgeAffinity::unit);
}

CsrGraph path_graph(std::int32_t n) {
  std::vector<WeightedEdge> edges;
  for (std::int32_t i = 0; i + 1 < n; ++i) edges.push_back({i, i + 1, 1.0});
  return graph_from_edges(n, edges);
}

CsrGraph cycle_graph(std::int32_t n) {
  std::vector<WeightedEdge> edges;
  for (std::int32_t i = 0; i < n; ++i) edges.push_back({i, (i + 1) % n, 1.0});
  return graph_from_edges(n, edges);
}

CsrGraph grid_graph(std::int32_t rows, std::int32_t cols) {
  std::vector<WeightedEdge> edges;
  for (std::int32_t r = 0; r < rows; ++r) {
    for (std::int32_t c = 0; c < cols; ++c) {
      if (c + 1 < cols) edges.push_back({r * cols + c, r * cols + c + 1, 1.0});
      if (r + 1 < rows) edges.push_back({r * cols + c, (r + 1) * cols + c, 1.0});
    }
  }
  return graph_from_edges(rows * cols, edges);
}

// ||L v - lambda v|| and ||V^T V - I||, and the null space's vectors first.
void expect_eigenpairs(const GraphLaplacian& g, const LaplacianEigenpairs& pairs,
                       double tolerance = 1e-10) {
  ASSERT_TRUE(pairs.ok) << pairs.message;
  const auto p = pairs.values.size();
  for (Eigen::Index j = 0; j < p; ++j) {
    const Eigen::VectorXd v = pairs.vectors.col(j);
    EXPECT_LT((g.matrix * v - pairs.values[j] * v).norm(), tolerance) << "pair " << j;
  }
  const Eigen::MatrixXd gram = pairs.vectors.transpose() * pairs.vectors;
  EXPECT_LT((gram - Eigen::MatrixXd::Identity(p, p)).norm(), tolerance);
  for (Eigen::Index j = 1; j < p; ++j) EXPECT_LE(pairs.values[j - 1], pairs.values[j] + 1e-12);
}

std::vector<double> path_eigenvalues(std::int32_t n) {
  std::vector<double> values;
  for (std::int32_t k = 0; k < n; ++k) {
    values.push_back(2.0 - 2.0 * std::cos(std::numbers::pi * k / n));
  }
  return values;
}

// Both paths (dense below kDenseLaplacianNodes, Lanczos above).
class PathSpectrum : public ::testing::TestWithParam<std::int32_t> {};

TEST_P(PathSpectrum, CombinatorialEigenvaluesAreTwoMinusTwoCosines) {
  const std::int32_t n = GetParam();
  const GraphLaplacian g = unit_laplacian(path_graph(n), LaplacianKind::combinatorial);
  const std::int32_t p = 16;
  const LaplacianEigenpairs pairs = smallest_laplacian_eigenpairs(g.matrix, g.null_space, p);
  expect_eigenpairs(g, pairs);
  EXPECT_EQ(pairs.dense, n <= kDenseLaplacianNodes);
  const std::vector<double> expected = path_eigenvalues(n);
  EXPECT_EQ(pairs.values[0], 0.0);
  for (std::int32_t k = 0; k < p; ++k) EXPECT_NEAR(pairs.values[k], expected[k], 1e-12) << k;
  // The eigenvector of lambda_1 is cos(pi k (i + 1/2) / n), up to sign and scale.
  Eigen::VectorXd fiedler(n);
  for (std::int32_t i = 0; i < n; ++i) fiedler[i] = std::cos(std::numbers::pi * (i + 0.5) / n);
  fiedler.normalize();  // its largest entry, at i = 0, is positive: the convention's sign
  EXPECT_LT((pairs.vectors.col(1) - fiedler).norm(), 1e-9);
}

INSTANTIATE_TEST_SUITE_P(DenseAndLanczos, PathSpectrum, ::testing::Values(40, 1000));

TEST(LaplacianEigensolver, CycleEigenvaluesComeInPairs) {
  const std::int32_t n = 600;
  const GraphLaplacian g = unit_laplacian(cycle_graph(n), LaplacianKind::combinatorial);
  const LaplacianEigenpairs pairs = smallest_laplacian_eigenpairs(g.matrix, g.null_space, 9);
  expect_eigenpairs(g, pairs);
  EXPECT_FALSE(pairs.dense);
  // 2 - 2 cos(2 pi k / n), k = 0, 1, 1, 2, 2, ...
  for (std::int32_t j = 0; j < 9; ++j) {
    const std::int32_t k = (j + 1) / 2;
    EXPECT_NEAR(pairs.values[j], 2.0 - 2.0 * std::cos(2.0 * std::numbers::pi * k / n), 1e-12);
  }
}

TEST(LaplacianEigensolver, GridEigenvaluesAreSumsOfPathEigenvalues) {
  for (const auto& [rows, cols] : {std::pair{7, 5}, std::pair{31, 23}}) {
    const GraphLaplacian g = unit_laplacian(grid_graph(rows, cols), LaplacianKind::combinatorial);
    const std::vector<double> a = path_eigenvalues(rows), b = path_eigenvalues(cols);
    std::vector<double> expected;
    for (const double x : a) {
      for (const double y : b) expected.push_back(x + y);
    }
    std::sort(expected.begin(), expected.end());
    const std::int32_t p = 24;
    const LaplacianEigenpairs pairs = smallest_laplacian_eigenpairs(g.matrix, g.null_space, p);
    expect_eigenpairs(g, pairs);
    for (std::int32_t k = 0; k < p; ++k) EXPECT_NEAR(pairs.values[k], expected[k], 1e-12);
  }
}

TEST(LaplacianEigensolver, EachComponentHasItsZeroEigenvalue) {
  // A path of 300 and a cycle of 200 side by side: two zero eigenvalues, the
  // indicators (unit norm) first, then the union of both spectra.
  std::vector<WeightedEdge> edges;
  for (std::int32_t i = 0; i + 1 < 300; ++i) edges.push_back({i, i + 1, 1.0});
  for (std::int32_t i = 0; i < 200; ++i) edges.push_back({300 + i, 300 + (i + 1) % 200, 1.0});
  for (const LaplacianKind kind : {LaplacianKind::combinatorial, LaplacianKind::normalized}) {
    const GraphLaplacian g = unit_laplacian(graph_from_edges(500, edges), kind);
    ASSERT_EQ(g.null_space.cols(), 2);
    const LaplacianEigenpairs pairs = smallest_laplacian_eigenpairs(g.matrix, g.null_space, 8);
    expect_eigenpairs(g, pairs);
    EXPECT_EQ(pairs.values[0], 0.0);
    EXPECT_EQ(pairs.values[1], 0.0);
    EXPECT_GT(pairs.values[2], 1e-6);
    // The components' indicators (D^1/2-weighted when normalized), in the order
    // of their smallest nodes.
    EXPECT_EQ(pairs.vectors.col(0).tail(200).norm(), 0.0);
    EXPECT_EQ(pairs.vectors.col(1).head(300).norm(), 0.0);
    EXPECT_NEAR(pairs.vectors(300, 1), 1.0 / std::sqrt(200.0), 1e-15);  // a cycle is regular
    if (kind == LaplacianKind::combinatorial) {
      EXPECT_NEAR(pairs.vectors(0, 0), 1.0 / std::sqrt(300.0), 1e-15);
      EXPECT_NEAR(pairs.vectors(150, 0), 1.0 / std::sqrt(300.0), 1e-15);
      std::vector<double> expected = path_eigenvalues(300);
      for (std::int32_t k = 0; k < 200; ++k) {
        expected.push_back(2.0 - 2.0 * std::cos(2.0 * std::numbers::pi * k / 200));
      }
      std::sort(expected.begin(), expected.end());
      for (std::int32_t k = 0; k < 8; ++k) EXPECT_NEAR(pairs.values[k], expected[k], 1e-12);
    } else {
      // sqrt(degree) / sqrt(sum of degrees): 1 at the path's ends, 2 inside.
      EXPECT_NEAR(pairs.vectors(0, 0), 1.0 / std::sqrt(598.0), 1e-15);
      EXPECT_NEAR(pairs.vectors(150, 0), std::sqrt(2.0 / 598.0), 1e-15);
    }
  }
}

// A random connected graph: a random spanning tree plus extra random edges, with
// random lengths.
CsrGraph random_graph(std::int32_t n, std::int32_t extra, std::uint64_t seed) {
  RandomStream random(seed, 0, 0);
  std::vector<WeightedEdge> edges;
  for (std::int32_t i = 1; i < n; ++i) {
    edges.push_back(
        {static_cast<std::int32_t>(random.uniform_index(i)), i, 0.1 + random.uniform()});
  }
  for (std::int32_t e = 0; e < extra; ++e) {
    edges.push_back({static_cast<std::int32_t>(random.uniform_index(n)),
                     static_cast<std::int32_t>(random.uniform_index(n)), 0.1 + random.uniform()});
  }
  return graph_from_edges(n, edges);
}

TEST(LaplacianEigensolver, MatchesTheDenseSolverOnRandomGraphs) {
  // Six small graphs (the dense path), two above kDenseLaplacianNodes (Lanczos).
  for (std::uint64_t seed = 1; seed <= 6; ++seed) {
    for (const std::int32_t n : {30, 200, 500}) {
      if (n > kDenseLaplacianNodes && seed > 1) continue;
      const CsrGraph graph = random_graph(n, n / 2, seed);
      const std::vector<std::uint8_t> all(static_cast<std::size_t>(n), 1);
      for (const LaplacianKind kind : {LaplacianKind::combinatorial, LaplacianKind::normalized}) {
        for (const EdgeAffinity affinity :
             {EdgeAffinity::unit, EdgeAffinity::distance, EdgeAffinity::gaussian}) {
          const GraphLaplacian g = graph_laplacian(graph, all, kind, affinity);
          const std::int32_t p = n == 30 ? 10 : 32;
          const LaplacianEigenpairs pairs =
              smallest_laplacian_eigenpairs(g.matrix, g.null_space, p);
          expect_eigenpairs(g, pairs);
          const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> dense{Eigen::MatrixXd(g.matrix)};
          for (std::int32_t k = 0; k < p; ++k) {
            EXPECT_NEAR(pairs.values[k], dense.eigenvalues()[k], 1e-10) << "seed " << seed;
          }
          // Well separated eigenvalues: the same vectors, by the sign convention.
          RowMatrixXd reference = dense.eigenvectors().leftCols(p);
          normalize_eigenvector_signs(reference);
          for (std::int32_t k = 1; k < p; ++k) {
            const double gap =
                std::min(dense.eigenvalues()[k] - dense.eigenvalues()[k - 1],
                         k + 1 < n ? dense.eigenvalues()[k + 1] - dense.eigenvalues()[k] : 1.0);
            if (gap < 1e-3) continue;
            EXPECT_LT((pairs.vectors.col(k) - reference.col(k)).norm(), 1e-8)
                << "seed " << seed << " n " << n << " pair " << k;
          }
        }
      }
    }
  }
}

TEST(LaplacianEigensolver, SignConventionIsDeterministic) {
  RowMatrixXd v(4, 3);
  v << 0.1, -0.5, 0.5,  //
      -0.9, 0.5, 0.1,   //
      0.2, 0.1, -0.5,   //
      0.0, 0.2, 0.3;
  normalize_eigenvector_signs(v);
  EXPECT_GT(v(1, 0), 0.0);  // largest magnitude -0.9: flipped
  EXPECT_GT(v(0, 1), 0.0);  // -0.5 and 0.5 tie: the lowest index decides, flipped
  EXPECT_GT(v(0, 2), 0.0);  // 0.5 and -0.5 tie: the lowest index is positive, kept
  for (Eigen::Index j = 0; j < 3; ++j) EXPECT_NEAR(v.col(j).norm(), 1.0, 1e-15);
  // The same graph twice: the same bits.
  const GraphLaplacian g = unit_laplacian(grid_graph(30, 30), LaplacianKind::normalized);
  const LaplacianEigenpairs a = smallest_laplacian_eigenpairs(g.matrix, g.null_space, 20);
  const LaplacianEigenpairs b = smallest_laplacian_eigenpairs(g.matrix, g.null_space, 20);
  ASSERT_TRUE(a.ok);
  EXPECT_EQ(a.vectors, b.vectors);
  EXPECT_EQ(a.values, b.values);
}

TEST(LaplacianEigensolver, RefusesMoreEigenpairsThanNodes) {
  const GraphLaplacian g = unit_laplacian(path_graph(5), LaplacianKind::combinatorial);
  EXPECT_THROW(smallest_laplacian_eigenpairs(g.matrix, g.null_space, 6), std::invalid_argument);
  const LaplacianEigenpairs all = smallest_laplacian_eigenpairs(g.matrix, g.null_space, 5);
  expect_eigenpairs(g, all);
}

}  // namespace
}  // namespace ggk::kernels

namespace ggk::kernels {
namespace {

// Two components whose node ids interleave: a path of `a` nodes on the even ids
// and a grid of rows x cols on the odd ids (then the rest of the grid's).
struct TwoComponents {
  CsrGraph graph;
  std::vector<std::int32_t> path_nodes, grid_nodes;
};

TwoComponents interleaved_path_and_grid(std::int32_t a, std::int32_t rows, std::int32_t cols) {
  TwoComponents two;
  const std::int32_t b = rows * cols;
  std::vector<std::int32_t> path_id(static_cast<std::size_t>(a)),
      grid_id(static_cast<std::size_t>(b));
  std::int32_t next = 0;
  for (std::int32_t i = 0; i < std::max(a, b); ++i) {
    if (i < a) path_id[static_cast<std::size_t>(i)] = next++;
    if (i < b) grid_id[static_cast<std::size_t>(i)] = next++;
  }
  std::vector<WeightedEdge> edges;
  for (std::int32_t i = 0; i + 1 < a; ++i) {
    edges.push_back(
        {path_id[static_cast<std::size_t>(i)], path_id[static_cast<std::size_t>(i + 1)], 1.0});
  }
  for (std::int32_t r = 0; r < rows; ++r) {
    for (std::int32_t c = 0; c < cols; ++c) {
      const auto id = [&](std::int32_t rr, std::int32_t cc) {
        return grid_id[static_cast<std::size_t>(rr * cols + cc)];
      };
      if (c + 1 < cols) edges.push_back({id(r, c), id(r, c + 1), 1.0});
      if (r + 1 < rows) edges.push_back({id(r, c), id(r + 1, c), 1.0});
    }
  }
  two.graph = graph_from_edges(a + b, edges);
  two.path_nodes = path_id;
  two.grid_nodes = grid_id;
  return two;
}

// The Laplacian of `graph` restricted to `nodes` (in the given order), as a graph
// of its own.
GraphLaplacian own_laplacian(const CsrGraph& graph, const std::vector<std::int32_t>& nodes,
                             LaplacianKind kind) {
  std::vector<std::int32_t> local(static_cast<std::size_t>(graph.num_nodes), -1);
  for (std::size_t i = 0; i < nodes.size(); ++i)
    local[static_cast<std::size_t>(nodes[i])] = static_cast<std::int32_t>(i);
  std::vector<WeightedEdge> edges;
  for (const std::int32_t u : nodes) {
    for (const std::int32_t v : graph.neighbors(u)) {
      if (u < v)
        edges.push_back(
            {local[static_cast<std::size_t>(u)], local[static_cast<std::size_t>(v)], 1.0});
    }
  }
  return unit_laplacian(graph_from_edges(static_cast<std::int32_t>(nodes.size()), edges), kind);
}

// Each vector is exactly zero off one component (leaking rounding, or a mixture of
// the two components' shared eigenvalues, is not), and the eigenvalues are the
// union of each component's own spectrum: Lanczos (a path of 300, a 15 x 12 grid)
// and the dense path (a path of 40, a 6 x 5 grid).
TEST(LaplacianEigensolver, SolvesEachComponentOnItsOwn) {
  for (const auto& [a, rows, cols] : {std::tuple{300, 15, 12}, std::tuple{40, 6, 5}}) {
    const TwoComponents two = interleaved_path_and_grid(a, rows, cols);
    for (const LaplacianKind kind : {LaplacianKind::combinatorial, LaplacianKind::normalized}) {
      const GraphLaplacian g = unit_laplacian(two.graph, kind);
      ASSERT_EQ(g.null_space.cols(), 2);
      const std::int32_t p = 24;
      const LaplacianEigenpairs pairs = smallest_laplacian_eigenpairs(g.matrix, g.null_space, p);
      expect_eigenpairs(g, pairs);
      const GraphLaplacian path = own_laplacian(two.graph, two.path_nodes, kind);
      const GraphLaplacian grid = own_laplacian(two.graph, two.grid_nodes, kind);
      const LaplacianEigenpairs path_pairs =
          smallest_laplacian_eigenpairs(path.matrix, path.null_space, p);
      const LaplacianEigenpairs grid_pairs =
          smallest_laplacian_eigenpairs(grid.matrix, grid.null_space, p);
      ASSERT_TRUE(path_pairs.ok && grid_pairs.ok);
      std::int32_t taken_path = 0, taken_grid = 0;
      for (std::int32_t j = 0; j < p; ++j) {
        double off_path = 0.0, off_grid = 0.0;  // the largest entry off each component
        for (const std::int32_t u : two.grid_nodes)
          off_path = std::max(off_path, std::abs(pairs.vectors(u, j)));
        for (const std::int32_t u : two.path_nodes)
          off_grid = std::max(off_grid, std::abs(pairs.vectors(u, j)));
        ASSERT_TRUE(off_path == 0.0 || off_grid == 0.0)
            << "pair " << j << " of " << a << " + " << rows << " x " << cols << ": " << off_path
            << " off the path, " << off_grid << " off the grid";
        // Each component's pairs in its own order, its own solve's values and vectors.
        const bool on_path = off_path == 0.0;
        const LaplacianEigenpairs& own = on_path ? path_pairs : grid_pairs;
        const std::vector<std::int32_t>& nodes = on_path ? two.path_nodes : two.grid_nodes;
        const std::int32_t k = on_path ? taken_path++ : taken_grid++;
        EXPECT_EQ(pairs.values[j], own.values[k]) << "pair " << j;
        for (std::size_t i = 0; i < nodes.size(); ++i) {
          EXPECT_NEAR(pairs.vectors(nodes[i], j), own.vectors(static_cast<Eigen::Index>(i), k),
                      1e-15)
              << "pair " << j << " node " << nodes[i];
        }
      }
    }
  }
}

}  // namespace
}  // namespace ggk::kernels

namespace ggk::kernels {
namespace {

// The tie rule: eigenvalues equal within kEigenvalueTieTolerance go by component
// (numbered by smallest node), then by order within it. The paths P3 (nodes 0-2:
// 0, 1, 3) and P6 (nodes 3-8: 0, 0.27, 1, 2, 3, 3.73) share 1 and 3, computed in
// two solves (not bit for bit equal): P3's comes first. And the cut through a
// tie is reported: lambda_p = lambda_(p+1) leaves the basis to the rule.
TEST(LaplacianEigensolver, TiesAcrossComponentsGoToTheLowestComponent) {
  std::vector<WeightedEdge> edges = {{0, 1, 1.0}, {1, 2, 1.0}};
  for (std::int32_t i = 3; i < 8; ++i) edges.push_back({i, i + 1, 1.0});
  const GraphLaplacian g = unit_laplacian(graph_from_edges(9, edges), LaplacianKind::combinatorial);
  const auto component_of = [&](const LaplacianEigenpairs& pairs, std::int32_t j) {
    return pairs.vectors.col(j).tail(6).norm() == 0.0   ? 0
           : pairs.vectors.col(j).head(3).norm() == 0.0 ? 1
                                                        : -1;
  };
  // p = 4: 0 (P3), 0 (P6), 0.27 (P6), 1 (P3); P6's 1 is not taken: a tie cut.
  const LaplacianEigenpairs four = smallest_laplacian_eigenpairs(g.matrix, g.null_space, 4);
  expect_eigenpairs(g, four, 1e-13);
  EXPECT_EQ(four.components, (std::vector<std::int32_t>{0, 1, 1, 0}));
  for (std::int32_t j = 0; j < 4; ++j) EXPECT_EQ(component_of(four, j), four.components[j]);
  EXPECT_NEAR(four.values[3], 1.0, 1e-14);
  EXPECT_NEAR(four.next_value, 1.0, 1e-14);
  EXPECT_TRUE(four.degenerate);
  // p = 5 takes both 1s (P3's first); the next, 2 (P6), is no tie.
  const LaplacianEigenpairs five = smallest_laplacian_eigenpairs(g.matrix, g.null_space, 5);
  EXPECT_EQ(five.components, (std::vector<std::int32_t>{0, 1, 1, 0, 1}));
  EXPECT_NEAR(five.next_value, 2.0, 1e-14);
  EXPECT_FALSE(five.degenerate);
  // p = 1: one of two zero eigenvalues, the first component's indicator.
  const LaplacianEigenpairs one = smallest_laplacian_eigenpairs(g.matrix, g.null_space, 1);
  EXPECT_EQ(one.components, (std::vector<std::int32_t>{0}));
  EXPECT_EQ(one.values[0], 0.0);
  EXPECT_EQ(one.next_value, 0.0);
  EXPECT_TRUE(one.degenerate);
  // All 9: both 3s, P3's first; nothing left.
  const LaplacianEigenpairs all = smallest_laplacian_eigenpairs(g.matrix, g.null_space, 9);
  expect_eigenpairs(g, all, 1e-13);
  EXPECT_EQ(all.components, (std::vector<std::int32_t>{0, 1, 1, 0, 1, 1, 0, 1, 1}));
  EXPECT_TRUE(std::isnan(all.next_value));
  EXPECT_FALSE(all.degenerate);
}

// A cut through a repeated eigenvalue of one connected graph is reported too:
// the cycle's 2 - 2 cos(2 pi k / n) come in pairs, by the dense path (40 nodes)
// and by Lanczos (600), whose next eigenvalue takes a solve of its own without
// changing the vectors taken.
TEST(LaplacianEigensolver, ReportsAnEigenvalueCutByTheCount) {
  for (const std::int32_t n : {40, 600}) {
    const GraphLaplacian g = unit_laplacian(cycle_graph(n), LaplacianKind::combinatorial);
    const auto cycle_value = [n](std::int32_t k) {
      return 2.0 - 2.0 * std::cos(2.0 * std::numbers::pi * k / n);
    };
    const LaplacianEigenpairs cut = smallest_laplacian_eigenpairs(g.matrix, g.null_space, 8);
    ASSERT_TRUE(cut.ok) << cut.message;
    EXPECT_TRUE(cut.degenerate) << n;
    EXPECT_NEAR(cut.next_value, cycle_value(4), 1e-12);
    EXPECT_EQ(cut.components, std::vector<std::int32_t>(8, 0));
    const LaplacianEigenpairs whole = smallest_laplacian_eigenpairs(g.matrix, g.null_space, 9);
    EXPECT_FALSE(whole.degenerate) << n;
    EXPECT_NEAR(whole.next_value, cycle_value(5), 1e-12);
  }
  // A path has simple eigenvalues: never a cut.
  const GraphLaplacian path = unit_laplacian(path_graph(300), LaplacianKind::normalized);
  const LaplacianEigenpairs pairs = smallest_laplacian_eigenpairs(path.matrix, path.null_space, 8);
  EXPECT_FALSE(pairs.degenerate);
  EXPECT_GT(pairs.next_value, pairs.values[7]);
}

}  // namespace
}  // namespace ggk::kernels
