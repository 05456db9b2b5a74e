// Proto-value functions (Mahadevan & Maggioni 2007): the graph Laplacian and its
// smallest eigenvectors as a state basis.
#include <pybind11/stl.h>

#include "kernels/graph_laplacian.hpp"
#include "kernels/laplacian_eigensolver.hpp"
#include "python/module/arrays.hpp"
#include "python/module/bindings.hpp"

namespace ggk::python {

namespace {

kernels::LaplacianKind laplacian_kind(const std::string& name) {
  return parse_choice<kernels::LaplacianKind>(
      "laplacian", name,
      {{"normalized", kernels::LaplacianKind::normalized},
       {"combinatorial", kernels::LaplacianKind::combinatorial}});
}

kernels::EdgeAffinity edge_affinity(const std::string& name) {
  return parse_choice<kernels::EdgeAffinity>("affinity", name,
                                             {{"unit", kernels::EdgeAffinity::unit},
                                              {"gaussian", kernels::EdgeAffinity::gaussian},
                                              {"distance", kernels::EdgeAffinity::distance}});
}

// The nodes flags: every node when none are given.
std::vector<std::uint8_t> node_flags(const kernels::CsrGraph& graph, const py::object& nodes) {
  if (nodes.is_none())
    return std::vector<std::uint8_t>(static_cast<std::size_t>(graph.num_nodes), 1);
  std::vector<std::uint8_t> flags = flags_from(nodes, "nodes");
  if (static_cast<std::int64_t>(flags.size()) != graph.num_nodes) {
    throw py::value_error("nodes has " + std::to_string(flags.size()) + " flags for a graph of " +
                          std::to_string(graph.num_nodes) + " nodes");
  }
  return flags;
}

}  // namespace

void bind_proto_value_functions(py::module_& module) {
  module.def(
      "graph_laplacian",
      [](const kernels::CsrGraph& graph, const py::object& nodes, const std::string& kind,
         const std::string& affinity) {
        const std::vector<std::uint8_t> flags = node_flags(graph, nodes);
        kernels::GraphLaplacian laplacian = [&] {
          py::gil_scoped_release release;
          return kernels::graph_laplacian(graph, flags, laplacian_kind(kind),
                                          edge_affinity(affinity));
        }();
        return py::make_tuple(to_numpy(std::move(laplacian.nodes)),
                              to_scipy_csc(std::move(laplacian.matrix)),
                              py::cast(std::move(laplacian.null_space)));
      },
      py::arg("graph"), py::arg("nodes") = py::none(), py::arg("laplacian") = "normalized",
      py::arg("affinity") = "unit",
      R"((nodes, L, null_space): the Laplacian over the graph's nodes (nodes: 0/1 flags
per graph node, default all), its rows the flagged nodes in id order.
laplacian "normalized" (I - D^-1/2 W D^-1/2) or "combinatorial" (D - W); affinity
W of an edge "unit" (1), "gaussian" (exp(-d^2 / 2 s^2), s the mean edge length) or
"distance" (d). null_space: one orthonormal column per connected component.)");

  module.def(
      "proto_value_functions",
      [](const kernels::CsrGraph& graph, std::int32_t count, const py::object& nodes,
         const std::string& kind, const std::string& affinity) {
        const std::vector<std::uint8_t> flags = node_flags(graph, nodes);
        const kernels::LaplacianKind laplacian_kind_value = laplacian_kind(kind);
        const kernels::EdgeAffinity affinity_value = edge_affinity(affinity);
        py::gil_scoped_release release;
        const kernels::GraphLaplacian laplacian =
            kernels::graph_laplacian(graph, flags, laplacian_kind_value, affinity_value);
        kernels::LaplacianEigenpairs pairs =
            kernels::smallest_laplacian_eigenpairs(laplacian.matrix, laplacian.null_space, count);
        if (!pairs.ok) {
          throw std::runtime_error("proto_value_functions: " + pairs.message);
        }
        // A row per graph node; a node outside `nodes` has none of the functions (zeros).
        kernels::RowMatrixXd node_values = kernels::RowMatrixXd::Zero(graph.num_nodes, count);
        for (std::size_t r = 0; r < laplacian.nodes.size(); ++r) {
          node_values.row(laplacian.nodes[r]) = pairs.vectors.row(static_cast<Eigen::Index>(r));
        }
        return std::make_pair(std::move(pairs.values), std::move(node_values));
      },
      py::arg("graph"), py::arg("count"), py::arg("nodes") = py::none(),
      py::arg("laplacian") = "normalized", py::arg("affinity") = "unit",
      R"((values, vectors): the count smallest eigenpairs of ggk.graph_laplacian's L,
ascending (each component's null vector first, exact zeros), vectors num_nodes x
count (zero rows off `nodes`): the proto-value functions, as the engine's PVF basis
takes them (unit norm, largest-magnitude entry positive).)");
}

}  // namespace ggk::python
