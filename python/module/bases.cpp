// ggk.copy_basis, ggk.shift_basis, ggk.table_basis: state kernels to the
// state-action bases LSPI reads (kernels/state_action_basis.hpp).
#include <pybind11/stl.h>

#include "kernels/action_block_system.hpp"
#include "kernels/state_action_basis.hpp"
#include "kernels/transition_model.hpp"
#include "python/module/arrays.hpp"
#include "python/module/bindings.hpp"
#include "python/module/state_action_basis.hpp"

namespace ggk::python {

std::int64_t StateActionBasis::num_states() const {
  return is_copy() ? state_kernels.rows() : table.rows() / num_actions;
}

std::int64_t StateActionBasis::num_features() const {
  return is_copy() ? state_kernels.cols() * num_actions : table.cols();
}

namespace {

void require_actions(std::int32_t num_actions) {
  if (num_actions < 1) throw py::value_error("num_actions must be >= 1");
}

}  // namespace

void bind_bases(py::module_& module) {
  py::class_<StateActionBasis>(module, "Basis", R"(A state-action basis for ggk.lspi.

phi(s, a) is row s * num_actions + a of `table`, in action-block form: action a's
features in columns [a p, (a + 1) p).)")
      .def_readonly("scheme", &StateActionBasis::scheme)
      .def_readonly("num_actions", &StateActionBasis::num_actions)
      .def_property_readonly("num_states", &StateActionBasis::num_states)
      .def_property_readonly("num_features", &StateActionBasis::num_features)
      .def_property_readonly(
          "state_kernels",
          [](const StateActionBasis& basis) -> py::object {
            if (!basis.is_copy()) return py::none();
            return to_scipy_csr(kernels::SparseRowMatrix(basis.state_kernels));
          },
          "The N x p state kernels of a copy basis (None for the others).")
      .def_property_readonly(
          "table",
          [](const StateActionBasis& basis) {
            return to_scipy_csr(basis.is_copy()
                                    ? kernels::copy_basis(basis.state_kernels, basis.num_actions)
                                    : kernels::SparseRowMatrix(basis.table));
          },
          "The (N m) x k feature table (formed on request for a copy basis).")
      .def("__repr__", [](const StateActionBasis& basis) {
        return "<ggk.Basis " + basis.scheme + ", " + std::to_string(basis.num_states()) +
               " states, " + std::to_string(basis.num_actions) + " actions, " +
               std::to_string(basis.num_features()) + " features>";
      });

  module.def(
      "copy_basis",
      [](const py::handle& state_kernels, std::int32_t num_actions) {
        require_actions(num_actions);
        return StateActionBasis{
            "copy", num_actions, sparse_rows_from(state_kernels, "state_kernels"), {}};
      },
      py::arg("state_kernels"), py::arg("num_actions"),
      R"(The copy scheme: phi_{a,j}(s, a) = K(s, c_j). state_kernels: N x p (scipy.sparse
or a 2-D array), e.g. ggk.geodesic_kernels or proto-value functions.)");

  module.def(
      "shift_basis",
      [](const py::handle& state_kernels, std::int32_t num_actions, const IntArray& states,
         const IntArray& actions, const IntArray& next_states, const py::object& weights) {
        require_actions(num_actions);
        kernels::SparseRowMatrix kernel_rows = sparse_rows_from(state_kernels, "state_kernels");
        DoubleArray weight_array =
            weights.is_none() ? DoubleArray(0) : DoubleArray::ensure(weights);
        if (!weight_array) throw py::value_error("weights must be an array of floats");
        const auto s = int_span(states, "states");
        const auto a = int_span(actions, "actions");
        const auto next = int_span(next_states, "next_states");
        const auto w = double_span(weight_array, "weights");
        kernels::SparseRowMatrix table = [&] {
          py::gil_scoped_release release;
          const kernels::EmpiricalTransitionModel model(
              static_cast<std::int32_t>(kernel_rows.rows()), num_actions, s, a, next, w);
          return kernels::shift_basis(kernel_rows, num_actions, model);
        }();
        return StateActionBasis{"shift", num_actions, {}, std::move(table)};
      },
      py::arg("state_kernels"), py::arg("num_actions"), py::arg("states"), py::arg("actions"),
      py::arg("next_states"), py::arg("weights") = py::none(),
      R"(The shift scheme, Eq. (9): phi_{a,j}(s, a) = sum_s' P(s'|s, a) K(s', c_j), P the
empirical model of the transitions (states, actions, next_states, optional
weights); an (s, a) never observed takes the copy scheme's row.)");

  module.def(
      "table_basis",
      [](const py::handle& table, std::int32_t num_actions) {
        require_actions(num_actions);
        kernels::SparseRowMatrix rows = sparse_rows_from(table, "table");
        if (rows.rows() % num_actions != 0) {
          throw py::value_error(
              "table has " + std::to_string(rows.rows()) +
              " rows, not a multiple of num_actions = " + std::to_string(num_actions));
        }
        const std::string violation = kernels::action_block_violation(rows, num_actions);
        if (!violation.empty()) {
          throw py::value_error("table is not in action-block form: " + violation);
        }
        return StateActionBasis{"table", num_actions, {}, std::move(rows)};
      },
      py::arg("table"), py::arg("num_actions"),
      "A feature table of one's own, (N m) x k in action-block form.");
}

}  // namespace ggk::python
