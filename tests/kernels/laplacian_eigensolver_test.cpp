#include "kernels/laplacian_eigensolver.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
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
