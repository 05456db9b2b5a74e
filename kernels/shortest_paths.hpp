#pragma once
// Single- and multi-source Dijkstra on a CsrGraph.
//
// Distances are +infinity for unreachable nodes. The multi-source form runs one
// Dijkstra per source as oneTBB tasks (nested parallelism composes with the
// caller's arena); each row depends only on its source, so the result is
// bit-identical for any thread count.

#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "kernels/csr_graph.hpp"
#include "kernels/eigen_types.hpp"

namespace ggk::kernels {

inline constexpr double kUnreachable = std::numeric_limits<double>::infinity();

// Reusable buffers for one Dijkstra at a time: an indexed 4-ary min-heap with
// decrease-key. Nothing is allocated per pop; buffers grow only when the graph does.
// Thread-safety: none; one workspace per worker.
class DijkstraWorkspace {
 public:
  void run(const CsrGraph& graph, std::int32_t source, std::span<double> distances);

 private:
  void push_or_decrease(std::int32_t node, std::span<const double> distances);
  std::int32_t pop_min(std::span<const double> distances);
  void sift_up(std::size_t slot, std::span<const double> distances);
  void sift_down(std::size_t slot, std::span<const double> distances);

  std::vector<std::int32_t> heap_;      // node ids ordered as a 4-ary heap on distance
  std::vector<std::int32_t> position_;  // slot of each node in heap_, -1 if absent
};

// Shortest-path distances from one source; distances.size() must equal num_nodes.
void shortest_path_distances(const CsrGraph& graph, std::int32_t source,
                             std::span<double> distances, DijkstraWorkspace& workspace);

// p x N row-major matrix: row i holds the distances from sources[i] to every node.
// Throws std::invalid_argument on an out-of-range source.
RowMatrixXd geodesic_distances(const CsrGraph& graph, std::span<const std::int32_t> sources);

}  // namespace ggk::kernels
