#include "kernels/graph_diagnostics.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

#include "kernels/shortest_paths.hpp"

namespace ggk::kernels {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// A 3 x 4 rectangle walked round three sides, and an isolated node:
//   3 (0,4) ---- 2 (3,4)
//                |
//   0 (0,0) ---- 1 (3,0)        4 (10,10), no edge
// Edges 0-1 (3), 1-2 (4), 2-3 (3); no edge 0-3, so SP(0,3) = 10 against ED 4.
struct Rectangle {
  RowMatrixXd states{{0.0, 0.0}, {3.0, 0.0}, {3.0, 4.0}, {0.0, 4.0}, {10.0, 10.0}};
  CsrGraph graph;
  Rectangle() {
    const std::vector<NodeTransition> moves = {{0, 1}, {1, 2}, {2, 3}, {1, 0}, {3, 2}};
    graph = transition_graph(states, moves);
  }
};

TEST(GraphDiagnostics, EdgeCountCountsNodePairsOnce) {
  const Rectangle r;
  EXPECT_EQ(undirected_edge_count(r.graph), 3);  // 6 arcs, 3 pairs
  const std::vector<WeightedEdge> arcs = {{0, 1, 1.0}, {1, 0, 1.0}, {1, 2, 1.0}};
  const CsrGraph directed = graph_from_edges(3, arcs, GraphDirection::directed);
  EXPECT_EQ(undirected_edge_count(directed), 2);  // {0,1} both ways, {1,2} one way
  EXPECT_EQ(undirected_edge_count(CsrGraph{}), 0);
}

TEST(GraphDiagnostics, MedianDegreeOverTheFlaggedNodes) {
  const Rectangle r;
  // Degrees 1, 2, 2, 1, 0.
  EXPECT_EQ(median_degree(r.graph, std::vector<std::uint8_t>{1, 1, 1, 1, 0}), 1.5);  // {1,1,2,2}
  EXPECT_EQ(median_degree(r.graph, std::vector<std::uint8_t>{1, 1, 1, 1, 1}), 1.0);  // {0,1,1,2,2}
  EXPECT_EQ(median_degree(r.graph, std::vector<std::uint8_t>{0, 1, 1, 0, 0}), 2.0);
  EXPECT_TRUE(std::isnan(median_degree(r.graph, std::vector<std::uint8_t>(5, 0))));
  EXPECT_THROW(median_degree(r.graph, std::vector<std::uint8_t>(4, 1)), std::invalid_argument);
}

TEST(GraphDiagnostics, GeodesicStretchIsTheMedianRatioOverFiniteCentrePairs) {
  const Rectangle r;
  // Shortest paths by hand from nodes 0..3; they match Dijkstra's.
  const RowMatrixXd sp{{0.0, 3.0, 7.0, 10.0, kInf},
                       {3.0, 0.0, 4.0, 7.0, kInf},
                       {7.0, 4.0, 0.0, 3.0, kInf},
                       {10.0, 7.0, 3.0, 0.0, kInf}};
  const std::vector<std::int32_t> all = {0, 1, 2, 3};
  EXPECT_EQ(geodesic_distances(r.graph, all), sp);

  // Pairs of {0, 1, 2, 3}: 3/3, 7/5, 10/4, 4/4, 7/5, 3/3 = {1, 1, 1, 1.4, 1.4, 2.5}.
  EXPECT_DOUBLE_EQ(geodesic_stretch(sp, all, r.states), 1.2);
  // Centres 0, 2, 3 (rows 0, 2, 3): 7/5, 10/4, 3/3 -> 1.4.
  const RowMatrixXd rows023 = (RowMatrixXd(3, 5) << sp.row(0), sp.row(2), sp.row(3)).finished();
  EXPECT_DOUBLE_EQ(geodesic_stretch(rows023, std::vector<std::int32_t>{0, 2, 3}, r.states), 1.4);
  // The isolated node 4 as a centre: its pairs are infinite and left out.
  const RowMatrixXd with4 = (RowMatrixXd(4, 5) << sp.row(0), sp.row(2), sp.row(3),
                             geodesic_distances(r.graph, std::vector<std::int32_t>{4}))
                                .finished();
  EXPECT_DOUBLE_EQ(geodesic_stretch(with4, std::vector<std::int32_t>{0, 2, 3, 4}, r.states), 1.4);
  EXPECT_TRUE(std::isnan(geodesic_stretch(sp.topRows(1), std::vector<std::int32_t>{0}, r.states)));
  // Two centres at the same point (ED 0) give no ratio.
  const RowMatrixXd twins{{0.0, 0.0}, {0.0, 0.0}};
  const RowMatrixXd twin_sp{{0.0, 1.0}, {1.0, 0.0}};
  EXPECT_TRUE(std::isnan(geodesic_stretch(twin_sp, std::vector<std::int32_t>{0, 1}, twins)));
  EXPECT_THROW(geodesic_stretch(sp.topRows(2), all, r.states), std::invalid_argument);
}

TEST(GraphDiagnostics, KernelGapSumsAbsoluteKernelDifferences) {
  // sigma 1: |1 - 1| + |exp(-1/2) - 1| + |0 - exp(-1/2)| = 1.
  EXPECT_DOUBLE_EQ(
      kernel_gap_sum(std::vector<double>{0.0, 1.0, kInf}, std::vector<double>{0.0, 0.0, 1.0}, 1.0),
      1.0);
  // sigma 2, SP 2 against ED 0: 1 - exp(-4 / 8).
  EXPECT_DOUBLE_EQ(kernel_gap_sum(std::vector<double>{2.0}, std::vector<double>{0.0}, 2.0),
                   1.0 - std::exp(-0.5));
  // Equal distances: no gap.
  EXPECT_EQ(kernel_gap_sum(std::vector<double>{1.0, 5.0}, std::vector<double>{1.0, 5.0}, 3.0), 0.0);
  EXPECT_THROW(kernel_gap_sum(std::vector<double>{1.0}, std::vector<double>{}, 1.0),
               std::invalid_argument);
}

}  // namespace
}  // namespace ggk::kernels
