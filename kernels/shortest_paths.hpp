#pragma once
// Single- and multi-source Dijkstra on a CsrGraph.
//
// Distances are +infinity for unreachable nodes. A node's distance is the
// smallest, over all paths from the source, of the path's weights added one
// after the other from the source, in double: the same bits as any textbook
// Dijkstra (binary heap, Boost.Graph) that relaxes d(v) = d(u) + w(u, v). The
// multi-source form runs one Dijkstra per source as oneTBB tasks (nested
// parallelism composes with the caller's arena); each row depends only on its
// source, so the result is bit-identical for any thread count.

#include <array>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "kernels/csr_graph.hpp"
#include "kernels/eigen_types.hpp"

namespace ggk::kernels {

inline constexpr double kUnreachable = std::numeric_limits<double>::infinity();

// Reusable buffers for one Dijkstra at a time: a radix heap (Ahuja, Mehlhorn,
// Orlin & Tarjan 1990) on the bit patterns of the non-negative double distances,
// which order like the doubles themselves. Dijkstra pops keys in non-decreasing
// order, the one property a radix heap needs; it is exact (no rounding of keys)
// and moves each entry only a few times. Entries are bare node ids: a node's key
// is its current distance, a node whose distance drops within its bucket is not
// pushed again, and an entry left behind in a higher bucket is dropped when met.
// Buffers grow only when the graph does; nothing is allocated per pop once warm.
// Thread-safety: none; one workspace per worker.
class DijkstraWorkspace {
 public:
  void run(const CsrGraph& graph, std::int32_t source, std::span<double> distances);

 private:
  // Bucket 0 holds nodes whose key equals last_; bucket b > 0 those whose key
  // differs from last_ first at bit b - 1 (keys above last_ only).
  static constexpr int kBuckets = 65;

  int bucket_of(std::uint64_t key) const;
  void push(int bucket, std::int32_t node);
  // Refills bucket 0 from the lowest non-empty bucket; false when the heap is empty.
  bool refill(const double* distances);

  std::array<std::vector<std::int32_t>, kBuckets> buckets_;
  std::uint64_t occupied_ = 0;  // bit b-1 set when bucket b > 0 may be non-empty
  std::uint64_t last_ = 0;      // key of the last refill's minimum
};

// Shortest-path distances from one source; distances.size() must equal num_nodes.
void shortest_path_distances(const CsrGraph& graph, std::int32_t source,
                             std::span<double> distances, DijkstraWorkspace& workspace);

// p x N row-major matrix: row i holds the distances from sources[i] to every node.
// Throws std::invalid_argument on an out-of-range source.
RowMatrixXd geodesic_distances(const CsrGraph& graph, std::span<const std::int32_t> sources);

}  // namespace ggk::kernels
