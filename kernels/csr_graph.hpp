#pragma once
// Compressed sparse row graph with non-negative edge weights.
//
// Node ids are int32 in [0, num_nodes); arc offsets are int64 so that graphs with
// more than 2^31 arcs still index correctly. An undirected edge is stored as two
// arcs. Within a row, neighbours are sorted by id (deterministic traversal order).
//
// Thread-safety: immutable after construction; share freely.

#include <cstdint>
#include <span>
#include <vector>

#include "kernels/eigen_types.hpp"

namespace ggk::kernels {

struct CsrGraph {
  std::int32_t num_nodes = 0;
  std::vector<std::int64_t> indptr{0};  // num_nodes + 1 offsets into indices/weights
  std::vector<std::int32_t> indices;    // arc heads
  std::vector<double> weights;          // arc weights, >= 0

  std::int64_t num_arcs() const { return static_cast<std::int64_t>(indices.size()); }
  std::span<const std::int32_t> neighbors(std::int32_t node) const {
    return {indices.data() + indptr[node], indices.data() + indptr[node + 1]};
  }
  std::span<const double> neighbor_weights(std::int32_t node) const {
    return {weights.data() + indptr[node], weights.data() + indptr[node + 1]};
  }
};

enum class GraphDirection { undirected, directed };

struct WeightedEdge {
  std::int32_t from;
  std::int32_t to;
  double weight;
};

struct NodeTransition {
  std::int32_t from;
  std::int32_t to;
};

// Builds a CSR graph from a list of weighted edges. Self-loops are dropped;
// duplicate edges between the same pair are merged, keeping the smallest weight.
// Throws std::invalid_argument on an out-of-range node id or a negative / NaN weight.
CsrGraph graph_from_edges(std::int32_t num_nodes, std::span<const WeightedEdge> edges,
                          GraphDirection direction = GraphDirection::undirected);

// The graph that observed transitions induce (paper sec. 3): node i has state
// vector node_states.row(i); every transition s -> s' with s != s' gives an edge
// of weight ||x_s - x_s'||_2.
CsrGraph transition_graph(const Eigen::Ref<const RowMatrixXd>& node_states,
                          std::span<const NodeTransition> transitions,
                          GraphDirection direction = GraphDirection::undirected);

struct ConnectedComponents {
  std::int32_t count = 0;
  std::vector<std::int32_t> labels;  // per node, in [0, count), numbered by smallest node id
};

// Weakly connected components (arcs followed in both directions).
ConnectedComponents connected_components(const CsrGraph& graph);

}  // namespace ggk::kernels
