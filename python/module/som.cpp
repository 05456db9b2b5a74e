// ggk.SelfOrganizingMap and ggk.train_som: the batch SOM that discretises
// continuous observations into graph nodes (paper sec. 4.2).
#include <optional>

#include <pybind11/stl.h>

#include "kernels/random_stream.hpp"
#include "kernels/self_organizing_map.hpp"
#include "python/module/arrays.hpp"
#include "python/module/bindings.hpp"

namespace ggk::python {

void bind_som(py::module_& module) {
  using kernels::SelfOrganizingMap;
  py::class_<SelfOrganizingMap>(module, "SelfOrganizingMap", R"(A trained (or given) SOM.

Unit u sits at grid (row, col) = (u // cols, u % cols); prototypes is units x d.)")
      .def(py::init([](std::int32_t rows, std::int32_t cols, kernels::RowMatrixXd prototypes) {
             return SelfOrganizingMap(rows, cols, std::move(prototypes));
           }),
           py::arg("rows"), py::arg("cols"), py::arg("prototypes"))
      .def_property_readonly("rows", &SelfOrganizingMap::rows)
      .def_property_readonly("cols", &SelfOrganizingMap::cols)
      .def_property_readonly("num_units", &SelfOrganizingMap::num_units)
      .def_property_readonly("prototypes", &SelfOrganizingMap::prototypes,
                             py::return_value_policy::reference_internal,
                             "units x d (a read-only view, no copy)")
      .def_property_readonly("quantization_errors", &SelfOrganizingMap::quantization_errors,
                             "per epoch, the mean distance of the samples to their best match")
      .def_property_readonly("radii", &SelfOrganizingMap::radii)
      .def("grid_coordinates", &SelfOrganizingMap::grid_coordinates)
      .def(
          "best_matching_units",
          [](const SelfOrganizingMap& som, const DenseIn& queries) {
            kernels::BestMatches matches = [&] {
              py::gil_scoped_release release;
              return som.best_matching_units(queries);
            }();
            return py::make_tuple(to_numpy(std::move(matches.units)),
                                  to_numpy(std::move(matches.distances)));
          },
          py::arg("queries"),
          R"((units, distances): every query row's nearest unit (ties to the lowest id) and
its Euclidean distance: n(s) and ||s - n(s)|| of the continuous geodesic kernel.)")
      .def("__repr__", [](const SelfOrganizingMap& som) {
        return "<ggk.SelfOrganizingMap " + std::to_string(som.rows()) + " x " +
               std::to_string(som.cols()) + ", dimension " + std::to_string(som.dimension()) + ">";
      });

  module.def(
      "som_grid",
      [](const DenseIn& samples) {
        const kernels::SomGrid grid = kernels::som_grid_for(samples);
        return py::make_tuple(grid.rows, grid.cols);
      },
      py::arg("samples"),
      "(rows, cols) by the SOM Toolbox's rule: about 5 sqrt(n) units, sides by the two "
      "leading principal components.");

  module.def(
      "train_som",
      [](const DenseIn& samples, std::optional<std::int32_t> rows, std::optional<std::int32_t> cols,
         std::int32_t epochs, std::optional<double> initial_radius, double final_radius,
         const std::string& schedule, const std::string& initialization, std::uint64_t seed) {
        kernels::SomOptions options;
        if (rows.has_value() != cols.has_value()) {
          throw py::value_error("give both rows and cols, or neither (the SOM Toolbox's grid)");
        }
        if (rows) {
          options.rows = *rows;
          options.cols = *cols;
        } else {
          const kernels::SomGrid grid = kernels::som_grid_for(samples);
          options.rows = grid.rows;
          options.cols = grid.cols;
        }
        options.epochs = epochs;
        options.initial_radius = initial_radius;
        options.final_radius = final_radius;
        options.radius_schedule = parse_choice<kernels::SomRadiusSchedule>(
            "schedule", schedule,
            {{"exponential", kernels::SomRadiusSchedule::exponential},
             {"linear", kernels::SomRadiusSchedule::linear}});
        options.initialization = parse_choice<kernels::SomInitialization>(
            "initialization", initialization,
            {{"principal_components", kernels::SomInitialization::principal_components},
             {"random_samples", kernels::SomInitialization::random_samples}});
        kernels::RandomStream random(seed, 0, 0);
        py::gil_scoped_release release;
        return kernels::train_self_organizing_map(samples, options, &random);
      },
      py::arg("samples"), py::arg("rows") = py::none(), py::arg("cols") = py::none(),
      py::arg("epochs") = 30, py::arg("initial_radius") = py::none(), py::arg("final_radius") = 1.0,
      py::arg("schedule") = "exponential", py::arg("initialization") = "principal_components",
      py::arg("seed") = 0,
      R"(A batch SOM on samples (n x d). rows, cols: the grid (default som_grid(samples));
radius from initial_radius (default max(rows, cols) / 2) to final_radius over the
epochs; initialization "principal_components" (deterministic) or
"random_samples" (drawn with seed). Bit-identical for any thread count.)");
}

}  // namespace ggk::python
