#pragma once
// The Laplacian of a sample graph, the operator whose smallest eigenvectors are
// the proto-value functions (Mahadevan & Maggioni 2007, JMLR 8, sec. 3).
//
// The rows are the graph's nodes (is_node[u] != 0) in id order; the affinity W of
// an edge is derived from the Euclidean length d the graph stores:
//   distance: W = d (the stored weight itself; no PVF paper uses it),
//   unit:     W = 1 (the papers' discrete MDPs: grid worlds, three rooms),
//   gaussian: W = exp(-d^2 / (2 s^2)), s the mean edge length of the graph (the
//             papers' continuous tasks use exp(-d^2 / delta) with delta set by hand).
// combinatorial: L = D - W; normalized: L = I - D^-1/2 W D^-1/2 (Chung), with
// L_uu = 0 for an isolated node; an edge of zero affinity (a zero length with
// `distance`, an underflowed Gaussian) is no edge. Both are symmetric positive
// semi-definite; a graph of c components (joined by edges of positive affinity)
// has exactly c zero eigenvalues, and `null_space` holds an
// orthonormal basis of their eigenspace: per component (numbered by its smallest
// node) the indicator 1_C (combinatorial) or D^1/2 1_C (normalized), unit norm; an
// isolated node's is its unit vector.
//
// Thread-safety: reentrant.

#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

#include "kernels/csr_graph.hpp"
#include "kernels/eigen_types.hpp"

namespace ggk::kernels {

enum class LaplacianKind { normalized, combinatorial };
enum class EdgeAffinity { distance, unit, gaussian };

std::string_view laplacian_kind_name(LaplacianKind kind);    // "normalized", "combinatorial"
std::string_view edge_affinity_name(EdgeAffinity affinity);  // "distance", "unit", "gaussian"

struct GraphLaplacian {
  std::vector<std::int32_t> nodes;  // the graph node of each row, ascending
  SparseColMatrix matrix;           // n x n, both triangles stored
  RowMatrixXd null_space;           // n x c, orthonormal, a column per component
};

// The Laplacian over the nodes of `graph` with is_node[u] != 0 (is_node has
// graph.num_nodes entries; arcs to non-nodes are refused with
// std::invalid_argument, as is an undirected graph whose arcs are not symmetric).
GraphLaplacian graph_laplacian(const CsrGraph& graph, std::span<const std::uint8_t> is_node,
                               LaplacianKind kind, EdgeAffinity affinity);

}  // namespace ggk::kernels
