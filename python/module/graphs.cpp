// ggk.Graph, the sample graph (paper sec. 3), and its shortest paths.
#include <pybind11/stl.h>

#include "kernels/csr_graph.hpp"
#include "kernels/shortest_paths.hpp"
#include "python/module/arrays.hpp"
#include "python/module/bindings.hpp"

namespace ggk::python {

namespace {

kernels::GraphDirection direction_of(bool directed) {
  return directed ? kernels::GraphDirection::directed : kernels::GraphDirection::undirected;
}

void require_same_length(std::size_t a, std::size_t b, const char* what) {
  if (a != b) {
    throw py::value_error(std::string(what) + " have different lengths (" + std::to_string(a) +
                          " and " + std::to_string(b) + ")");
  }
}

}  // namespace

void bind_graphs(py::module_& module) {
  py::class_<kernels::CsrGraph>(module, "Graph", R"(A graph in compressed sparse rows.

Node ids are 0 .. num_nodes - 1; an undirected edge is two arcs; within a row the
neighbours are sorted by id. Built by ggk.transition_graph or ggk.graph_from_edges.)")
      .def_property_readonly("num_nodes", [](const kernels::CsrGraph& g) { return g.num_nodes; })
      .def_property_readonly("num_arcs", &kernels::CsrGraph::num_arcs)
      .def_property_readonly(
          "indptr",
          [](const kernels::CsrGraph& g) {
            return py::array_t<std::int64_t>(g.indptr.size(), g.indptr.data());
          },
          "Row offsets into indices and weights (num_nodes + 1, int64; a copy).")
      .def_property_readonly(
          "indices",
          [](const kernels::CsrGraph& g) {
            return py::array_t<std::int32_t>(g.indices.size(), g.indices.data());
          },
          "Arc heads (int32; a copy).")
      .def_property_readonly(
          "weights",
          [](const kernels::CsrGraph& g) {
            return py::array_t<double>(g.weights.size(), g.weights.data());
          },
          "Arc weights (a copy).")
      .def(
          "to_scipy",
          [](const kernels::CsrGraph& g) {
            py::module_ sparse = py::module_::import("scipy.sparse");
            return sparse.attr("csr_matrix")(
                py::make_tuple(py::array_t<double>(g.weights.size(), g.weights.data()),
                               py::array_t<std::int32_t>(g.indices.size(), g.indices.data()),
                               py::array_t<std::int64_t>(g.indptr.size(), g.indptr.data())),
                py::arg("shape") = py::make_tuple(g.num_nodes, g.num_nodes));
          },
          "The weighted adjacency as a scipy.sparse.csr_matrix (for scipy.sparse.csgraph).")
      .def(
          "connected_components",
          [](const kernels::CsrGraph& g) {
            kernels::ConnectedComponents components = kernels::connected_components(g);
            return py::make_tuple(components.count, to_numpy(std::move(components.labels)));
          },
          "(count, labels): weakly connected components, numbered by their smallest node.")
      .def("__repr__", [](const kernels::CsrGraph& g) {
        return "<ggk.Graph " + std::to_string(g.num_nodes) + " nodes, " +
               std::to_string(g.num_arcs()) + " arcs>";
      });

  module.def(
      "transition_graph",
      [](const DenseIn& node_states, const IntArray& from, const IntArray& to, bool directed) {
        const auto sources = int_span(from, "from_nodes");
        const auto targets = int_span(to, "to_nodes");
        require_same_length(sources.size(), targets.size(), "from_nodes and to_nodes");
        std::vector<kernels::NodeTransition> transitions(sources.size());
        for (std::size_t i = 0; i < sources.size(); ++i) transitions[i] = {sources[i], targets[i]};
        py::gil_scoped_release release;
        return kernels::transition_graph(node_states, transitions, direction_of(directed));
      },
      py::arg("node_states"), py::arg("from_nodes"), py::arg("to_nodes"),
      py::arg("directed") = false,
      R"(The graph that observed transitions induce (paper sec. 3).

node_states: N x d, row i the state vector of node i. Every transition
from_nodes[i] -> to_nodes[i] between different nodes is an edge of weight
||x_from - x_to||_2 (an undirected edge unless directed).)");

  module.def(
      "graph_from_edges",
      [](std::int32_t num_nodes, const IntArray& from, const IntArray& to,
         const DoubleArray& weights, bool directed) {
        const auto sources = int_span(from, "from_nodes");
        const auto targets = int_span(to, "to_nodes");
        const auto w = double_span(weights, "weights");
        require_same_length(sources.size(), targets.size(), "from_nodes and to_nodes");
        require_same_length(sources.size(), w.size(), "from_nodes and weights");
        std::vector<kernels::WeightedEdge> edges(sources.size());
        for (std::size_t i = 0; i < sources.size(); ++i) edges[i] = {sources[i], targets[i], w[i]};
        py::gil_scoped_release release;
        return kernels::graph_from_edges(num_nodes, edges, direction_of(directed));
      },
      py::arg("num_nodes"), py::arg("from_nodes"), py::arg("to_nodes"), py::arg("weights"),
      py::arg("directed") = false,
      "A graph from weighted edges; self-loops dropped, a repeated edge keeps its smallest "
      "weight.");

  module.def(
      "shortest_paths",
      [](const kernels::CsrGraph& graph, const IntArray& sources) {
        const auto ids = int_span(sources, "sources");
        py::gil_scoped_release release;
        return kernels::geodesic_distances(graph, ids);
      },
      py::arg("graph"), py::arg("sources"),
      R"(p x N shortest-path distances: row i from sources[i] to every node (inf where
unreachable). One Dijkstra per source, in parallel (oneTBB); the bits of a
textbook Dijkstra, for any thread count.)");
}

}  // namespace ggk::python
