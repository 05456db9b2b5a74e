#include "kernels/graph_laplacian.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace ggk::kernels {

std::string_view laplacian_kind_name(LaplacianKind kind) {
  return kind == LaplacianKind::normalized ? "normalized" : "combinatorial";
}

std::string_view edge_affinity_name(EdgeAffinity affinity) {
  switch (affinity) {
    case EdgeAffinity::distance:
      return "distance";
    case EdgeAffinity::unit:
      return "unit";
    case EdgeAffinity::gaussian:
      break;
  }
  return "gaussian";
}

GraphLaplacian graph_laplacian(const CsrGraph& graph, std::span<const std::uint8_t> is_node,
                               LaplacianKind kind, EdgeAffinity affinity) {
  if (is_node.size() != static_cast<std::size_t>(graph.num_nodes)) {
    throw std::invalid_argument("graph_laplacian: is_node has " + std::to_string(is_node.size()) +
                                " entries for a graph of " + std::to_string(graph.num_nodes) +
                                " nodes");
  }
  GraphLaplacian laplacian;
  std::vector<std::int32_t> row_of(static_cast<std::size_t>(graph.num_nodes), -1);
  for (std::int32_t u = 0; u < graph.num_nodes; ++u) {
    if (is_node[static_cast<std::size_t>(u)] == 0) continue;
    row_of[static_cast<std::size_t>(u)] = static_cast<std::int32_t>(laplacian.nodes.size());
    laplacian.nodes.push_back(u);
  }
  const auto n = static_cast<std::int32_t>(laplacian.nodes.size());

  // The Gaussian affinity's width: the mean edge (arc) length, summed in arc order.
  double width = 0.0;
  if (affinity == EdgeAffinity::gaussian && graph.num_arcs() > 0) {
    double sum = 0.0;
    for (const double d : graph.weights) sum += d;
    width = sum / static_cast<double>(graph.num_arcs());
  }
  auto affinity_of = [&](double d) {
    switch (affinity) {
      case EdgeAffinity::distance:
        return d;
      case EdgeAffinity::unit:
        return 1.0;
      case EdgeAffinity::gaussian:
        break;
    }
    return width > 0.0 ? std::exp(-d * d / (2.0 * width * width)) : 1.0;
  };

  std::vector<double> degree(static_cast<std::size_t>(n), 0.0);
  for (std::int32_t r = 0; r < n; ++r) {
    const std::int32_t u = laplacian.nodes[static_cast<std::size_t>(r)];
    const auto heads = graph.neighbors(u);
    const auto lengths = graph.neighbor_weights(u);
    for (std::size_t k = 0; k < heads.size(); ++k) {
      if (row_of[static_cast<std::size_t>(heads[k])] < 0) {
        throw std::invalid_argument("graph_laplacian: arc " + std::to_string(u) + " -> " +
                                    std::to_string(heads[k]) + " leads to a node not in the set");
      }
      degree[static_cast<std::size_t>(r)] += affinity_of(lengths[k]);
    }
  }

  // Both triangles, column by column (the graph is symmetric: column u = row u).
  std::vector<Eigen::Triplet<double, std::int32_t>> entries;
  entries.reserve(static_cast<std::size_t>(n) + static_cast<std::size_t>(graph.num_arcs()));
  for (std::int32_t r = 0; r < n; ++r) {
    const std::int32_t u = laplacian.nodes[static_cast<std::size_t>(r)];
    const double du = degree[static_cast<std::size_t>(r)];
    const auto heads = graph.neighbors(u);
    const auto lengths = graph.neighbor_weights(u);
    bool diagonal_done = false;
    auto add_diagonal = [&] {
      if (kind == LaplacianKind::combinatorial) {
        entries.emplace_back(r, r, du);
      } else if (du > 0.0) {
        entries.emplace_back(r, r, 1.0);
      }
      diagonal_done = true;
    };
    for (std::size_t k = 0; k < heads.size(); ++k) {
      const std::int32_t c = row_of[static_cast<std::size_t>(heads[k])];
      if (!diagonal_done && c > r) add_diagonal();
      const double w = affinity_of(lengths[k]);
      if (w == 0.0) continue;  // no edge: a zero length, or a Gaussian affinity underflowed
      const double value = kind == LaplacianKind::combinatorial
                               ? -w
                               : -w / std::sqrt(du * degree[static_cast<std::size_t>(c)]);
      entries.emplace_back(c, r, value);
    }
    if (!diagonal_done) add_diagonal();
  }
  laplacian.matrix.resize(n, n);
  laplacian.matrix.setFromTriplets(entries.begin(), entries.end());
  laplacian.matrix.makeCompressed();
  const SparseColMatrix transposed = laplacian.matrix.transpose();
  if ((transposed - laplacian.matrix).norm() != 0.0) {
    throw std::invalid_argument("graph_laplacian: the graph's arcs are not symmetric");
  }

  // The null space: one unit vector per component of the edges of positive
  // affinity (those the matrix holds), supported on it.
  CsrGraph subgraph;
  subgraph.num_nodes = n;
  subgraph.indptr.assign(1, 0);
  for (std::int32_t r = 0; r < n; ++r) {
    const std::int32_t u = laplacian.nodes[static_cast<std::size_t>(r)];
    const auto heads = graph.neighbors(u);
    const auto lengths = graph.neighbor_weights(u);
    for (std::size_t k = 0; k < heads.size(); ++k) {
      if (affinity_of(lengths[k]) == 0.0) continue;
      subgraph.indices.push_back(row_of[static_cast<std::size_t>(heads[k])]);
      subgraph.weights.push_back(1.0);
    }
    subgraph.indptr.push_back(static_cast<std::int64_t>(subgraph.indices.size()));
  }
  const ConnectedComponents components = connected_components(subgraph);
  laplacian.null_space = RowMatrixXd::Zero(n, components.count);
  for (std::int32_t r = 0; r < n; ++r) {
    const double du = degree[static_cast<std::size_t>(r)];
    const bool weighted = kind == LaplacianKind::normalized && du > 0.0;
    laplacian.null_space(r, components.labels[static_cast<std::size_t>(r)]) =
        weighted ? std::sqrt(du) : 1.0;
  }
  for (Eigen::Index c = 0; c < laplacian.null_space.cols(); ++c) {
    laplacian.null_space.col(c) /= laplacian.null_space.col(c).norm();
  }
  return laplacian;
}

}  // namespace ggk::kernels
