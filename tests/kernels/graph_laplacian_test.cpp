#include "kernels/graph_laplacian.hpp"

#include <cmath>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

namespace ggk::kernels {
namespace {

// 0 -(2)- 1 -(1)- 2, and node 3 (not a node) alone.
CsrGraph small_path() {
  return graph_from_edges(4, std::vector<WeightedEdge>{{0, 1, 2.0}, {1, 2, 1.0}});
}

TEST(GraphLaplacian, CombinatorialIsDegreeMinusAffinity) {
  const std::vector<std::uint8_t> is_node = {1, 1, 1, 0};
  const GraphLaplacian unit =
      graph_laplacian(small_path(), is_node, LaplacianKind::combinatorial, EdgeAffinity::unit);
  EXPECT_EQ(unit.nodes, (std::vector<std::int32_t>{0, 1, 2}));
  Eigen::MatrixXd expected(3, 3);
  expected << 1, -1, 0, -1, 2, -1, 0, -1, 1;
  EXPECT_EQ(Eigen::MatrixXd(unit.matrix), expected);
  const GraphLaplacian distance =
      graph_laplacian(small_path(), is_node, LaplacianKind::combinatorial, EdgeAffinity::distance);
  expected << 2, -2, 0, -2, 3, -1, 0, -1, 1;
  EXPECT_EQ(Eigen::MatrixXd(distance.matrix), expected);
  // One component: the constant vector, unit norm.
  ASSERT_EQ(unit.null_space.cols(), 1);
  EXPECT_NEAR(unit.null_space(0, 0), 1.0 / std::sqrt(3.0), 1e-15);
  EXPECT_NEAR((Eigen::MatrixXd(unit.matrix) * unit.null_space).norm(), 0.0, 1e-15);
}

TEST(GraphLaplacian, GaussianAffinityUsesTheMeanEdgeLength) {
  const std::vector<std::uint8_t> is_node = {1, 1, 1, 0};
  const GraphLaplacian g =
      graph_laplacian(small_path(), is_node, LaplacianKind::combinatorial, EdgeAffinity::gaussian);
  const double s = 1.5;  // (2 + 2 + 1 + 1) / 4 arcs
  EXPECT_DOUBLE_EQ(g.matrix.coeff(0, 1), -std::exp(-4.0 / (2 * s * s)));
  EXPECT_DOUBLE_EQ(g.matrix.coeff(1, 2), -std::exp(-1.0 / (2 * s * s)));
}

TEST(GraphLaplacian, NormalizedHasUnitDiagonalAndWeightedNullVectors) {
  const std::vector<std::uint8_t> is_node = {1, 1, 1, 1};  // node 3 isolated
  const GraphLaplacian g =
      graph_laplacian(small_path(), is_node, LaplacianKind::normalized, EdgeAffinity::unit);
  const Eigen::MatrixXd dense(g.matrix);
  EXPECT_EQ(dense(0, 0), 1.0);
  EXPECT_EQ(dense(3, 3), 0.0);  // an isolated node's row is zero
  EXPECT_DOUBLE_EQ(dense(0, 1), -1.0 / std::sqrt(2.0));
  ASSERT_EQ(g.null_space.cols(), 2);  // two components
  EXPECT_NEAR((dense * g.null_space).norm(), 0.0, 1e-15);
  EXPECT_NEAR((g.null_space.transpose() * g.null_space - Eigen::MatrixXd::Identity(2, 2)).norm(),
              0.0, 1e-15);
  EXPECT_DOUBLE_EQ(g.null_space(1, 0), std::sqrt(2.0) / 2.0);  // sqrt(2) / sqrt(1 + 2 + 1)
  EXPECT_EQ(g.null_space(3, 1), 1.0);
}

TEST(GraphLaplacian, AZeroAffinityIsNoEdge) {
  // Nodes 0 and 1 at the same place (length 0): with distance affinities they are
  // not joined, so the graph has two components and no 0 / 0 entry.
  const CsrGraph graph = graph_from_edges(3, std::vector<WeightedEdge>{{0, 1, 0.0}, {1, 2, 2.0}});
  const std::vector<std::uint8_t> all = {1, 1, 1};
  const GraphLaplacian g =
      graph_laplacian(graph, all, LaplacianKind::normalized, EdgeAffinity::distance);
  EXPECT_TRUE(Eigen::MatrixXd(g.matrix).allFinite());
  EXPECT_EQ(g.matrix.coeff(0, 0), 0.0);
  EXPECT_EQ(g.null_space.cols(), 2);
  EXPECT_NEAR((Eigen::MatrixXd(g.matrix) * g.null_space).norm(), 0.0, 1e-15);
}

TEST(GraphLaplacian, RefusesArcsToNodesOutsideTheSet) {
  const std::vector<std::uint8_t> is_node = {1, 1, 0, 0};
  EXPECT_THROW(
      graph_laplacian(small_path(), is_node, LaplacianKind::normalized, EdgeAffinity::unit),
      std::invalid_argument);
  EXPECT_THROW(graph_laplacian(small_path(), std::vector<std::uint8_t>{1, 1},
                               LaplacianKind::normalized, EdgeAffinity::unit),
               std::invalid_argument);
}

}  // namespace
}  // namespace ggk::kernels
