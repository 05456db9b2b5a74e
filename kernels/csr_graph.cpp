#include "kernels/csr_graph.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace ggk::kernels {

CsrGraph graph_from_edges(std::int32_t num_nodes, std::span<const WeightedEdge> edges,
                          GraphDirection direction) {
  if (num_nodes < 0) throw std::invalid_argument("graph_from_edges: negative node count");
  std::vector<WeightedEdge> arcs;
  arcs.reserve(edges.size() * (direction == GraphDirection::undirected ? 2 : 1));
  for (std::size_t i = 0; i < edges.size(); ++i) {
    const WeightedEdge& e = edges[i];
    if (e.from < 0 || e.from >= num_nodes || e.to < 0 || e.to >= num_nodes) {
      throw std::invalid_argument("graph_from_edges: edge " + std::to_string(i) + " (" +
                                  std::to_string(e.from) + " -> " + std::to_string(e.to) +
                                  ") has a node id outside [0, " + std::to_string(num_nodes) + ")");
    }
    if (!(e.weight >= 0.0)) {
      throw std::invalid_argument("graph_from_edges: edge " + std::to_string(i) +
                                  " has a negative or NaN weight");
    }
    if (e.from == e.to) continue;
    arcs.push_back(e);
    if (direction == GraphDirection::undirected) arcs.push_back({e.to, e.from, e.weight});
  }
  // Sorting by (from, to, weight) puts the smallest weight of each pair first.
  std::sort(arcs.begin(), arcs.end(), [](const WeightedEdge& a, const WeightedEdge& b) {
    if (a.from != b.from) return a.from < b.from;
    if (a.to != b.to) return a.to < b.to;
    return a.weight < b.weight;
  });
  arcs.erase(std::unique(arcs.begin(), arcs.end(),
                         [](const WeightedEdge& a, const WeightedEdge& b) {
                           return a.from == b.from && a.to == b.to;
                         }),
             arcs.end());

  CsrGraph graph;
  graph.num_nodes = num_nodes;
  graph.indptr.assign(static_cast<std::size_t>(num_nodes) + 1, 0);
  graph.indices.reserve(arcs.size());
  graph.weights.reserve(arcs.size());
  for (const WeightedEdge& a : arcs) {
    ++graph.indptr[static_cast<std::size_t>(a.from) + 1];
    graph.indices.push_back(a.to);
    graph.weights.push_back(a.weight);
  }
  for (std::size_t i = 1; i < graph.indptr.size(); ++i) graph.indptr[i] += graph.indptr[i - 1];
  return graph;
}

CsrGraph transition_graph(const Eigen::Ref<const RowMatrixXd>& node_states,
                          std::span<const NodeTransition> transitions, GraphDirection direction) {
  const auto num_nodes = static_cast<std::int32_t>(node_states.rows());
  std::vector<WeightedEdge> edges;
  edges.reserve(transitions.size());
  for (std::size_t i = 0; i < transitions.size(); ++i) {
    const NodeTransition& t = transitions[i];
    if (t.from < 0 || t.from >= num_nodes || t.to < 0 || t.to >= num_nodes) {
      throw std::invalid_argument("transition_graph: transition " + std::to_string(i) +
                                  " has a node id outside [0, " + std::to_string(num_nodes) + ")");
    }
    if (t.from == t.to) continue;
    edges.push_back({t.from, t.to, (node_states.row(t.from) - node_states.row(t.to)).norm()});
  }
  return graph_from_edges(num_nodes, edges, direction);
}

ConnectedComponents connected_components(const CsrGraph& graph) {
  // Union-find over arcs, then labels numbered in order of each component's
  // smallest node id (deterministic).
  std::vector<std::int32_t> parent(static_cast<std::size_t>(graph.num_nodes));
  for (std::int32_t i = 0; i < graph.num_nodes; ++i) parent[i] = i;
  auto find = [&parent](std::int32_t x) {
    while (parent[x] != x) {
      parent[x] = parent[parent[x]];
      x = parent[x];
    }
    return x;
  };
  for (std::int32_t u = 0; u < graph.num_nodes; ++u) {
    for (std::int32_t v : graph.neighbors(u)) {
      const std::int32_t ru = find(u);
      const std::int32_t rv = find(v);
      if (ru != rv) parent[std::max(ru, rv)] = std::min(ru, rv);
    }
  }
  ConnectedComponents result;
  result.labels.assign(static_cast<std::size_t>(graph.num_nodes), -1);
  std::vector<std::int32_t> root_label(static_cast<std::size_t>(graph.num_nodes), -1);
  for (std::int32_t u = 0; u < graph.num_nodes; ++u) {
    const std::int32_t r = find(u);
    if (root_label[r] < 0) root_label[r] = result.count++;
    result.labels[u] = root_label[r];
  }
  return result;
}

}  // namespace ggk::kernels
