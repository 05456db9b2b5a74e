#pragma once
// The nearest visited state of every state, for the continuous form of the
// geodesic Gaussian kernel on a finite state set (a state off the sample graph
// is joined to its nearest graph node). Pure numerics, no I/O.
//
// Thread-safety: reentrant; the queries run as oneTBB tasks.

#include <cstdint>
#include <vector>

#include "kernels/eigen_types.hpp"

namespace ggk::kernels {

// For every state (row of state_vectors), the nearest visited state (itself when
// visited) and the Euclidean distance to it, (row(s) - row(v)).norm(); ties go
// to the lowest state id, exactly as a scan over the visited states in id order.
// With no visited state, every unvisited state gets state 0 at infinite distance.
// GGK values of unvisited states follow the continuous form
// SP(s, c) = ED(s, n(s)) + SP(n(s), c). A k-d tree: O(n log n) on grids (a scan
// over the visited states would be O(n^2)). Queries run as oneTBB tasks.
void nearest_visited_states(const RowMatrixXd& state_vectors,
                            const std::vector<std::uint8_t>& visited,
                            std::vector<std::int32_t>& nearest, std::vector<double>& distance);

}  // namespace ggk::kernels
