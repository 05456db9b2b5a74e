#include "engine/tasks/pvf_basis.hpp"

#include <algorithm>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "kernels/graph_laplacian.hpp"
#include "kernels/laplacian_eigensolver.hpp"

namespace ggk::engine {

std::vector<std::int32_t> pvf_counts(std::span<const SweepPoint> points, std::int32_t nodes) {
  std::vector<std::int32_t> counts;
  for (const SweepPoint& point : points) {
    if (point.basis == KernelType::pvf && point.kernels <= nodes) counts.push_back(point.kernels);
  }
  std::sort(counts.begin(), counts.end());
  counts.erase(std::unique(counts.begin(), counts.end()), counts.end());
  return counts;
}

const RunEigenbasis& RunEigenbases::of(std::int32_t p) const {
  const auto found = by_count.find(p);
  if (found == by_count.end()) {
    throw std::logic_error("no eigenbasis of " + std::to_string(p) + " vectors was computed");
  }
  return found->second;
}

RunEigenbases run_eigenbases(const kernels::CsrGraph& graph, std::span<const std::uint8_t> is_node,
                             const PvfSettings& settings, std::span<const SweepPoint> points) {
  RunEigenbases bases;
  const auto nodes = static_cast<std::int32_t>(
      std::count_if(is_node.begin(), is_node.end(), [](std::uint8_t flag) { return flag != 0; }));
  const std::vector<std::int32_t> counts = pvf_counts(points, nodes);
  if (counts.empty()) return bases;
  const kernels::GraphLaplacian laplacian =
      kernels::graph_laplacian(graph, is_node, settings.laplacian, settings.edge_weights);
  for (const std::int32_t count : counts) {
    RunEigenbasis& basis = bases.by_count[count];
    kernels::LaplacianEigenpairs pairs =
        kernels::smallest_laplacian_eigenpairs(laplacian.matrix, laplacian.null_space, count);
    if (!pairs.ok) {
      basis.ok = false;
      basis.message = pairs.message;
      continue;
    }
    basis.next_value = pairs.next_value;
    basis.degenerate = pairs.degenerate;
    basis.values = std::move(pairs.values);
    basis.node_values = kernels::RowMatrixXd::Zero(graph.num_nodes, count);
    for (std::size_t r = 0; r < laplacian.nodes.size(); ++r) {
      basis.node_values.row(laplacian.nodes[r]) = pairs.vectors.row(static_cast<Eigen::Index>(r));
    }
  }
  return bases;
}

kernels::SparseRowMatrix pvf_state_table(const RunEigenbasis& basis,
                                         std::span<const std::int32_t> node_of, std::int32_t p) {
  const auto n = static_cast<Eigen::Index>(node_of.size());
  kernels::SparseRowMatrix table(n, p);
  table.reserve(Eigen::VectorXi::Constant(n, p));
  for (Eigen::Index i = 0; i < n; ++i) {
    const auto values = basis.node_values.row(node_of[static_cast<std::size_t>(i)]);
    for (Eigen::Index j = 0; j < p; ++j) {
      if (values[j] != 0.0) table.insert(i, j) = values[j];
    }
  }
  table.makeCompressed();
  return table;
}

PvfRowTable pvf_row_table(const RunEigenbasis& basis, std::span<const std::int32_t> node_of,
                          std::int32_t p) {
  std::vector<std::int32_t> row_of_node(static_cast<std::size_t>(basis.node_values.rows()), -1);
  for (const std::int32_t node : node_of) row_of_node[static_cast<std::size_t>(node)] = 0;
  std::vector<std::int32_t> nodes;
  for (std::size_t node = 0; node < row_of_node.size(); ++node) {
    if (row_of_node[node] < 0) continue;
    row_of_node[node] = static_cast<std::int32_t>(nodes.size());
    nodes.push_back(static_cast<std::int32_t>(node));
  }
  PvfRowTable table;
  table.rows = pvf_state_table(basis, nodes, p);
  table.row_of_state.reserve(node_of.size());
  for (const std::int32_t node : node_of) {
    table.row_of_state.push_back(row_of_node[static_cast<std::size_t>(node)]);
  }
  return table;
}

std::string eigenbasis_warning(const RunEigenbasis& basis) {
  if (!basis.ok || !basis.degenerate) return {};
  const std::string p = std::to_string(basis.values.size());
  const std::string q = std::to_string(basis.values.size() + 1);
  char values[96];
  std::snprintf(values, sizeof values, "%.17g and %.17g) are equal within %g",
                basis.values[basis.values.size() - 1], basis.next_value,
                kernels::kEigenvalueTieTolerance);
  return "the Laplacian's eigenvalues lambda_" + p + " and lambda_" + q + " (" + values +
         " x its largest diagonal entry" +
         ": the basis is not determined by the graph (the eigensolver's tie rule picks which " +
         "vectors of the eigenspace the " + p + " proto-value functions take)";
}

NamedArray eigenvalue_array(const RunEigenbasis& basis) {
  return {"laplacian_eigenvalues",
          {static_cast<std::int64_t>(basis.values.size())},
          std::vector<double>(basis.values.data(), basis.values.data() + basis.values.size())};
}

}  // namespace ggk::engine
