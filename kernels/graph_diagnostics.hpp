#pragma once
// Diagnostics that say whether geodesic Gaussian kernels can differ from ordinary
// ones on a given sample graph: the graph's size and degree, how much longer
// shortest paths are than straight lines between kernel centres, and how far the
// two kernels' values lie apart. Pure functions, no I/O.
//
// Definitions (the summary columns of the same names, engine/tasks/README.md):
//   edges             undirected edges of the graph (node pairs joined by an arc).
//   median_degree     median, over the nodes flagged as graph nodes, of the number
//                     of neighbours (mean of the two middle values for an even
//                     count; NaN with no node).
//   geodesic_stretch  median over the unordered pairs {c_i, c_j}, i < j, of the
//                     given centres of SP(c_i, c_j) / ED(c_i, c_j), over the pairs
//                     whose SP is finite and whose ED is > 0 (NaN with none).
//                     SP from the Dijkstra rows of the centres, ED between the
//                     nodes' state vectors. With ED edge weights SP >= ED, so the
//                     stretch is >= 1; 1 means straight lines are graph paths.
//   kernel_gap        mean over states s and centres c of
//                     |exp(-SP(s,c)^2 / 2 sigma^2) - exp(-ED(s,c)^2 / 2 sigma^2)|
//                     (Eqs. (7) and (8), untruncated; an infinite SP gives 0).
//
// Thread-safety: reentrant; no shared state.

#include <cstdint>
#include <span>

#include "kernels/csr_graph.hpp"
#include "kernels/eigen_types.hpp"

namespace ggk::kernels {

// Node pairs {u, v}, u != v, joined by an arc in either direction.
std::int64_t undirected_edge_count(const CsrGraph& graph);

// Median neighbour count over the nodes u with is_node[u] != 0 (size num_nodes).
double median_degree(const CsrGraph& graph, std::span<const std::uint8_t> is_node);

// center_distances: row i holds SP from centers[i] to every node (at least
// centers.size() rows); node_states: one row per node.
double geodesic_stretch(const Eigen::Ref<const RowMatrixXd>& center_distances,
                        std::span<const std::int32_t> centers,
                        const Eigen::Ref<const RowMatrixXd>& node_states);

// The sum over i of |exp(-g_i^2 / 2 sigma^2) - exp(-e_i^2 / 2 sigma^2)|, for the
// geodesic distances g and the Euclidean distances e of the same (state, centre)
// pairs (equal lengths). kernel_gap = the sum over all pairs / their count.
double kernel_gap_sum(std::span<const double> geodesic, std::span<const double> euclidean,
                      double sigma);

}  // namespace ggk::kernels
