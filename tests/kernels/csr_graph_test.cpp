#include "kernels/csr_graph.hpp"

#include <cmath>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

namespace ggk::kernels {
namespace {

TEST(CsrGraph, UndirectedEdgesAreStoredBothWaysSortedAndMerged) {
  const std::vector<WeightedEdge> edges = {
      {0, 2, 5.0}, {2, 0, 3.0}, {1, 1, 9.0}, {0, 1, 1.0}, {0, 2, 4.0}};
  const CsrGraph g = graph_from_edges(3, edges);
  EXPECT_EQ(g.num_nodes, 3);
  EXPECT_EQ(g.indptr, (std::vector<std::int64_t>{0, 2, 3, 4}));
  EXPECT_EQ(g.indices, (std::vector<std::int32_t>{1, 2, 0, 0}));
  // Duplicates keep the smallest weight; the self-loop 1 -> 1 is dropped.
  EXPECT_EQ(g.weights, (std::vector<double>{1.0, 3.0, 1.0, 3.0}));
}

TEST(CsrGraph, DirectedEdgesKeepTheirDirection) {
  const std::vector<WeightedEdge> edges = {{0, 1, 2.0}, {2, 1, 1.0}};
  const CsrGraph g = graph_from_edges(3, edges, GraphDirection::directed);
  EXPECT_EQ(g.indptr, (std::vector<std::int64_t>{0, 1, 1, 2}));
  EXPECT_EQ(g.indices, (std::vector<std::int32_t>{1, 1}));
  EXPECT_TRUE(g.neighbors(1).empty());
}

TEST(CsrGraph, RejectsBadEdges) {
  const std::vector<WeightedEdge> out_of_range = {{0, 3, 1.0}};
  EXPECT_THROW(graph_from_edges(3, out_of_range), std::invalid_argument);
  const std::vector<WeightedEdge> negative = {{0, 1, -1.0}};
  EXPECT_THROW(graph_from_edges(3, negative), std::invalid_argument);
  const std::vector<WeightedEdge> nan = {{0, 1, std::nan("")}};
  EXPECT_THROW(graph_from_edges(3, nan), std::invalid_argument);
}

TEST(CsrGraph, TransitionGraphWeighsEdgesByEuclideanDistance) {
  RowMatrixXd states(3, 2);
  states << 0, 0, 3, 4, 3, 0;
  const std::vector<NodeTransition> transitions = {{0, 1}, {1, 1}, {1, 2}, {1, 0}};
  const CsrGraph g = transition_graph(states, transitions);
  ASSERT_EQ(g.indptr, (std::vector<std::int64_t>{0, 1, 3, 4}));
  EXPECT_EQ(g.indices, (std::vector<std::int32_t>{1, 0, 2, 1}));
  EXPECT_EQ(g.weights, (std::vector<double>{5.0, 5.0, 4.0, 4.0}));
  const std::vector<NodeTransition> bad = {{0, 5}};
  EXPECT_THROW(transition_graph(states, bad), std::invalid_argument);
}

TEST(CsrGraph, ConnectedComponentsAreNumberedBySmallestNode) {
  const std::vector<WeightedEdge> edges = {{4, 2, 1.0}, {1, 3, 1.0}, {3, 5, 1.0}};
  const CsrGraph g = graph_from_edges(6, edges);
  const ConnectedComponents c = connected_components(g);
  EXPECT_EQ(c.count, 3);
  EXPECT_EQ(c.labels, (std::vector<std::int32_t>{0, 1, 2, 1, 2, 1}));
  // Directed arcs still join a weak component.
  const std::vector<WeightedEdge> directed = {{2, 0, 1.0}};
  EXPECT_EQ(connected_components(graph_from_edges(3, directed, GraphDirection::directed)).count, 2);
}

}  // namespace
}  // namespace ggk::kernels
