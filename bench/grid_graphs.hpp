#pragma once
// Grid graphs for the benchmarks: rows x cols nodes, 4-neighbour edges of unit
// weight (the arm's 5-degree joint grid is 37 x 72).

#include <cstdint>
#include <vector>

#include "kernels/csr_graph.hpp"

namespace ggk::bench {

inline kernels::CsrGraph grid_graph(std::int32_t rows, std::int32_t cols) {
  std::vector<kernels::WeightedEdge> edges;
  edges.reserve(static_cast<std::size_t>(rows) * cols * 2);
  for (std::int32_t r = 0; r < rows; ++r) {
    for (std::int32_t c = 0; c < cols; ++c) {
      const std::int32_t u = r * cols + c;
      if (c + 1 < cols) edges.push_back({u, u + 1, 1.0});
      if (r + 1 < rows) edges.push_back({u, u + cols, 1.0});
    }
  }
  return kernels::graph_from_edges(rows * cols, edges);
}

// p sources spread evenly over the node ids.
inline std::vector<std::int32_t> spread_sources(std::int32_t num_nodes, std::int32_t p) {
  std::vector<std::int32_t> sources(static_cast<std::size_t>(p));
  for (std::int32_t i = 0; i < p; ++i) {
    sources[static_cast<std::size_t>(i)] =
        static_cast<std::int32_t>(static_cast<std::int64_t>(i) * num_nodes / p);
  }
  return sources;
}

}  // namespace ggk::bench
