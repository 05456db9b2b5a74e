#pragma once
// The proto-value functions of a run (basis "pvf"): the smallest eigenvectors of
// the sample graph's Laplacian ([pvf] laplacian, edge_weights; kernels/
// graph_laplacian.hpp), on the graph the GGK uses. Each kernel count p of the
// run's "pvf" points is solved on its own, for its p smallest eigenpairs, and
// shared by the fits of that count: a fit's basis depends only on its run and its
// own count, never on which other counts the job sweeps (Lanczos vectors for p
// eigenpairs are not bit for bit the first p of a larger solve), so a study grown
// by a kernel count equals it from scratch. Each fit stores its p eigenvalues.
// On a graph of several components each eigenvector lives on one component,
// exact zeros elsewhere (kernels/laplacian_eigensolver.hpp): a component no
// reward reaches gets Q = 0 exactly. When the p-th and (p+1)-th eigenvalues are
// tied the graph does not determine the basis: the fit carries a warning.
//
// States off the graph: the value of the nearest graph node, n(s) of the
// continuous GGK (kernels/nearest_visited.hpp; for Khepera the nearest occupied
// SOM unit). The Nystrom extension (Mahadevan & Maggioni 2006) is not used: its
// values depend on the affinity's width off the graph, which the unit affinity
// does not have, and nearest-node values are what the GGK of the same fit sees.
// The sweep's sigma does not enter a PVF fit ([basis] truncation neither: an
// eigenvector's entries have no common scale to cut at).
//
// Thread-safety: read-only once built; shared by the fits of a run.

#include <cstdint>
#include <map>
#include <span>
#include <string>
#include <vector>

#include "engine/job/job_spec.hpp"
#include "engine/job/sweep.hpp"
#include "engine/tasks/run_record.hpp"
#include "kernels/csr_graph.hpp"
#include "kernels/eigen_types.hpp"

namespace ggk::engine {

struct RunEigenbasis {
  bool ok = true;
  std::string message;     // why the eigensolve failed; empty when ok
  Eigen::VectorXd values;  // the Laplacian's smallest eigenvalues, ascending (P)
  // graph.num_nodes x P: row u the eigenvectors' entries at node u (zero for a
  // non-node); each eigenvector has unit norm over the nodes.
  kernels::RowMatrixXd node_values;
  double next_value = 0.0;  // lambda_(P+1); NaN when P = nodes or unknown
  bool degenerate = false;  // lambda_P and lambda_(P+1) tied: the basis is the solver's pick
};

// The distinct kernel counts of the points with basis "pvf" that are at most
// `nodes`, ascending (more kernels than nodes: an invalid fit); empty when no
// point asks for the basis.
std::vector<std::int32_t> pvf_counts(std::span<const SweepPoint> points, std::int32_t nodes);

// The eigenbases of a run, by kernel count.
struct RunEigenbases {
  std::map<std::int32_t, RunEigenbasis> by_count;
  // The basis of count p (one of pvf_counts); throws std::logic_error otherwise.
  const RunEigenbasis& of(std::int32_t p) const;
};

// The eigenbasis of `graph` over its nodes (is_node[u] != 0) for each of
// pvf_counts(points); empty when no point has basis "pvf".
RunEigenbases run_eigenbases(const kernels::CsrGraph& graph, std::span<const std::uint8_t> is_node,
                             const PvfSettings& settings, std::span<const SweepPoint> points);

// The state table of a fit with p proto-value functions: row i = the first p
// entries of node_values at node node_of[i] (the state's own node, or its nearest).
kernels::SparseRowMatrix pvf_state_table(const RunEigenbasis& basis,
                                         std::span<const std::int32_t> node_of, std::int32_t p);

// pvf_state_table with each distinct row once: `rows` holds the rows of the
// distinct nodes of node_of (ascending node order), row_of_state[i] the row of
// state i's node. For fit_lspi_pooled_copy_basis: the Khepera's 20,200 readings
// take the values of at most 696 SOM units.
struct PvfRowTable {
  kernels::SparseRowMatrix rows;
  std::vector<std::int32_t> row_of_state;
};
PvfRowTable pvf_row_table(const RunEigenbasis& basis, std::span<const std::int32_t> node_of,
                          std::int32_t p);

// The warning of a fit on `basis` (FitRecord::warning): when its last
// eigenvalue ties with the next, which vectors of the eigenspace the fit uses is
// the eigensolver's choice, not the graph's; empty otherwise.
std::string eigenbasis_warning(const RunEigenbasis& basis);

// A fit's eigenvalues as its array "laplacian_eigenvalues" (p values).
NamedArray eigenvalue_array(const RunEigenbasis& basis);

}  // namespace ggk::engine
