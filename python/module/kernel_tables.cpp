// State kernel tables: ordinary (Eq. 7), geodesic (Eq. 8) and the continuous
// geodesic kernel for states off the graph (paper sec. 4.2), and the nearest
// visited state that the latter joins a state to.
#include <pybind11/stl.h>

#include "kernels/gaussian_kernels.hpp"
#include "kernels/nearest_visited.hpp"
#include "python/module/arrays.hpp"
#include "python/module/bindings.hpp"

namespace ggk::python {

void bind_kernel_tables(py::module_& module) {
  module.def(
      "ordinary_kernels",
      [](const DenseIn& states, const DenseIn& centers, double sigma, double truncation) {
        kernels::SparseRowMatrix table = [&] {
          py::gil_scoped_release release;
          return kernels::ordinary_gaussian_kernels(states, centers, sigma, truncation);
        }();
        return to_scipy_csr(std::move(table));
      },
      py::arg("states"), py::arg("centers"), py::arg("sigma"), py::arg("truncation") = 0.0,
      R"(N x p ordinary Gaussian kernels, Eq. (7): exp(-||s_i - c_j||^2 / (2 sigma^2)),
values below truncation dropped (scipy.sparse.csr_matrix). states N x d, centers
p x d.)");

  module.def(
      "geodesic_kernels",
      [](const DenseIn& center_distances, double sigma, double truncation) {
        kernels::SparseRowMatrix table = [&] {
          py::gil_scoped_release release;
          return kernels::geodesic_gaussian_kernels(center_distances, sigma, truncation);
        }();
        return to_scipy_csr(std::move(table));
      },
      py::arg("center_distances"), py::arg("sigma"), py::arg("truncation") = 0.0,
      R"(N x p geodesic Gaussian kernels, Eq. (8), on graph nodes: center_distances is
ggk.shortest_paths(graph, centers) (p x N); an unreachable node's value is 0.)");

  module.def(
      "continuous_geodesic_kernels",
      [](const IntArray& nearest_node, const DoubleArray& distance_to_nearest,
         const DenseIn& center_distances, double sigma, double truncation) {
        const auto nodes = int_span(nearest_node, "nearest_node");
        const auto distances = double_span(distance_to_nearest, "distance_to_nearest");
        kernels::SparseRowMatrix table = [&] {
          py::gil_scoped_release release;
          return kernels::continuous_geodesic_gaussian_kernels(nodes, distances, center_distances,
                                                               sigma, truncation);
        }();
        return to_scipy_csr(std::move(table));
      },
      py::arg("nearest_node"), py::arg("distance_to_nearest"), py::arg("center_distances"),
      py::arg("sigma"), py::arg("truncation") = 0.0,
      R"(Geodesic Gaussian kernels of states off the graph (paper sec. 4.2):
SP(s, c) = ||s - n(s)|| + SP(n(s), c), n(s) = nearest_node[i] at distance
distance_to_nearest[i] (e.g. SelfOrganizingMap.best_matching_units of new
observations); center_distances as for geodesic_kernels.)");

  module.def(
      "nearest_visited_states",
      [](const kernels::RowMatrixXd& state_vectors, const py::handle& visited) {
        const std::vector<std::uint8_t> flags = flags_from(visited, "visited");
        if (static_cast<Eigen::Index>(flags.size()) != state_vectors.rows()) {
          throw py::value_error("visited has " + std::to_string(flags.size()) + " flags for " +
                                std::to_string(state_vectors.rows()) + " states");
        }
        std::vector<std::int32_t> nearest;
        std::vector<double> distance;
        {
          py::gil_scoped_release release;
          kernels::nearest_visited_states(state_vectors, flags, nearest, distance);
        }
        return py::make_tuple(to_numpy(std::move(nearest)), to_numpy(std::move(distance)));
      },
      py::arg("state_vectors"), py::arg("visited"),
      R"((nearest, distance): every state's nearest visited state (itself when visited)
and the Euclidean distance to it, ties to the lowest id.)");
}

}  // namespace ggk::python
