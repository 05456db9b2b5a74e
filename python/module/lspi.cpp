// ggk.Samples, ggk.lspi and ggk.LspiFit: least-squares policy iteration over a
// batch of samples and a state-action basis (kernels/lspi.hpp).
#include <limits>

#include <pybind11/stl.h>

#include "kernels/first_best.hpp"
#include "kernels/lspi.hpp"
#include "kernels/sample_batch.hpp"
#include "python/module/arrays.hpp"
#include "python/module/bindings.hpp"
#include "python/module/state_action_basis.hpp"

namespace ggk::python {

namespace {

// A finished fit and what its greedy policy needs to act on new states.
struct LspiFit {
  kernels::LspiResult result;
  std::string scheme;  // the basis's
  std::int32_t num_actions = 0;
  std::int64_t row_width = 0;  // columns of what the policy reads: p (copy) or k (others)
};

kernels::SampleBatch make_batch(const IntArray& states, const IntArray& actions,
                                const DoubleArray& rewards, const IntArray& next_states,
                                const py::object& terminals, const py::object& weights) {
  const auto s = int_span(states, "states");
  const auto a = int_span(actions, "actions");
  const auto r = double_span(rewards, "rewards");
  const auto next = int_span(next_states, "next_states");
  const std::size_t n = s.size();
  if (a.size() != n || r.size() != n || next.size() != n) {
    throw py::value_error("states, actions, rewards and next_states must have one length (" +
                          std::to_string(n) + ", " + std::to_string(a.size()) + ", " +
                          std::to_string(r.size()) + ", " + std::to_string(next.size()) + ")");
  }
  const std::vector<std::uint8_t> ends =
      terminals.is_none() ? std::vector<std::uint8_t>(n, 0) : flags_from(terminals, "terminals");
  std::vector<double> w(n, 1.0);
  if (!weights.is_none()) {
    const auto given = DoubleArray::ensure(weights);
    if (!given) throw py::value_error("weights must be an array of floats");
    const auto span = double_span(given, "weights");
    w.assign(span.begin(), span.end());
  }
  if (ends.size() != n || w.size() != n) {
    throw py::value_error("terminals and weights must have one entry per sample (" +
                          std::to_string(n) + ")");
  }
  kernels::SampleBatch batch;
  batch.states.assign(s.begin(), s.end());
  batch.actions.assign(a.begin(), a.end());
  batch.rewards.assign(r.begin(), r.end());
  batch.next_states.assign(next.begin(), next.end());
  batch.terminals = ends;
  batch.weights = std::move(w);
  return batch;
}

// ggk.Samples, or a mapping with the constructor's names.
kernels::SampleBatch batch_from(const py::handle& samples) {
  if (py::isinstance<kernels::SampleBatch>(samples)) return samples.cast<kernels::SampleBatch>();
  if (!py::isinstance<py::dict>(samples)) {
    throw py::type_error(
        "samples must be ggk.Samples or a dict with states, actions, rewards, "
        "next_states (and terminals, weights)");
  }
  const auto mapping = samples.cast<py::dict>();
  const auto get = [&](const char* key) -> py::object {
    if (mapping.contains(key)) return mapping[key];
    return py::none();
  };
  for (const char* key : {"states", "actions", "rewards", "next_states"}) {
    if (!mapping.contains(key))
      throw py::value_error(std::string("samples has no \"") + key + "\"");
  }
  return make_batch(IntArray::ensure(get("states")), IntArray::ensure(get("actions")),
                    DoubleArray::ensure(get("rewards")), IntArray::ensure(get("next_states")),
                    get("terminals"), get("weights"));
}

kernels::LspiOptions lspi_options(const std::string& solver, double gamma, double ridge,
                                  const std::string& ridge_scale, std::int32_t max_iterations,
                                  const std::string& stopping, double weight_tolerance,
                                  const std::string& linear_algebra, double min_rcond,
                                  bool keep_iterates) {
  kernels::LspiOptions options;
  options.solver = parse_choice<kernels::LspiSolver>(
      "solver", solver, {{"brm", kernels::LspiSolver::brm}, {"lstdq", kernels::LspiSolver::lstdq}});
  options.gamma = gamma;
  options.ridge = ridge;
  options.ridge_scale = parse_choice<kernels::RidgeScale>(
      "ridge_scale", ridge_scale,
      {{"absolute", kernels::RidgeScale::absolute}, {"relative", kernels::RidgeScale::relative}});
  options.max_iterations = max_iterations;
  options.stopping =
      parse_choice<kernels::LspiStopping>("stopping", stopping,
                                          {{"policy", kernels::LspiStopping::policy_unchanged},
                                           {"weights", kernels::LspiStopping::weights_converged}});
  options.weight_tolerance = weight_tolerance;
  options.linear_algebra =
      parse_choice<kernels::LinearAlgebra>("linear_algebra", linear_algebra,
                                           {{"auto", kernels::LinearAlgebra::automatic},
                                            {"sparse", kernels::LinearAlgebra::sparse},
                                            {"dense", kernels::LinearAlgebra::dense}});
  options.solver_settings.min_rcond = min_rcond;
  options.keep_iterates = keep_iterates;
  return options;
}

// True when the policy's argument is one state's row (a 1-D array), not a matrix.
bool is_one_row(const py::handle& rows) {
  return !py::module_::import("scipy.sparse").attr("issparse")(rows).cast<bool>() &&
         py::module_::import("numpy").attr("ndim")(rows).cast<int>() == 1;
}

// Q(s, a) of the states whose rows `rows` holds: a copy basis reads one row of p
// state kernels per state (Q(s, a) = w_a . k(s), summed as the engine's greedy
// step over observations does), the others m rows of k features per state.
kernels::RowMatrixXd action_values(const LspiFit& fit, const py::handle& rows) {
  if (fit.result.weights.size() == 0) {
    throw py::value_error("this fit has no weights (status " +
                          std::string(kernels::to_string(fit.result.status)) + ": " +
                          fit.result.message + ")");
  }
  py::object matrix = py::reinterpret_borrow<py::object>(rows);
  if (is_one_row(rows)) matrix = py::module_::import("numpy").attr("atleast_2d")(rows);
  const kernels::SparseRowMatrix table = sparse_rows_from(matrix, "the policy's argument");
  const std::int32_t m = fit.num_actions;
  if (table.cols() != fit.row_width) {
    throw py::value_error("the policy reads rows of " + std::to_string(fit.row_width) +
                          (fit.scheme == "copy" ? " state kernels" : " features") + ", not " +
                          std::to_string(table.cols()));
  }
  const Eigen::VectorXd& w = fit.result.weights;
  if (fit.scheme == "copy") {
    kernels::RowMatrixXd q(table.rows(), m);
    Eigen::VectorXd k(fit.row_width);
    for (Eigen::Index i = 0; i < table.rows(); ++i) {
      k.setZero();
      for (kernels::SparseRowMatrix::InnerIterator it(table, i); it; ++it) k(it.col()) = it.value();
      for (std::int32_t a = 0; a < m; ++a)
        q(i, a) = w.segment(a * fit.row_width, fit.row_width).dot(k);
    }
    return q;
  }
  if (table.rows() % m != 0) {
    throw py::value_error("the policy reads " + std::to_string(m) +
                          " feature rows per state, phi(s, 0) .. phi(s, m - 1); got " +
                          std::to_string(table.rows()) + " rows");
  }
  const Eigen::VectorXd values = table * w;
  kernels::RowMatrixXd q(table.rows() / m, m);
  for (Eigen::Index i = 0; i < q.size(); ++i) q.data()[i] = values(i);
  return q;
}

py::object greedy_actions(const LspiFit& fit, const py::handle& rows) {
  const kernels::RowMatrixXd q = action_values(fit, rows);
  std::vector<std::int32_t> actions(static_cast<std::size_t>(q.rows()));
  for (Eigen::Index i = 0; i < q.rows(); ++i) {
    actions[static_cast<std::size_t>(i)] =
        kernels::first_best(q.data() + i * q.cols(), fit.num_actions);
  }
  if (is_one_row(rows)) return py::int_(actions.front());
  return to_numpy(std::move(actions));
}

}  // namespace

void bind_lspi(py::module_& module) {
  py::class_<kernels::SampleBatch>(module, "Samples", R"(A batch of transitions for LSPI.

Sample i is (states[i], actions[i], rewards[i], next_states[i], terminals[i]) with
weight weights[i]; states index the basis's states (row s * m + a of its table is
phi(s, a)). terminals: 1 where the episode ended (s' does not bootstrap).)")
      .def(py::init(&make_batch), py::arg("states"), py::arg("actions"), py::arg("rewards"),
           py::arg("next_states"), py::arg("terminals") = py::none(),
           py::arg("weights") = py::none())
      .def("__len__", &kernels::SampleBatch::size)
      .def_property_readonly(
          "states", [](const kernels::SampleBatch& b) { return py::array(py::cast(b.states)); })
      .def_property_readonly(
          "actions", [](const kernels::SampleBatch& b) { return py::array(py::cast(b.actions)); })
      .def_property_readonly(
          "rewards", [](const kernels::SampleBatch& b) { return py::array(py::cast(b.rewards)); })
      .def_property_readonly(
          "next_states",
          [](const kernels::SampleBatch& b) { return py::array(py::cast(b.next_states)); })
      .def_property_readonly(
          "terminals",
          [](const kernels::SampleBatch& b) { return py::array(py::cast(b.terminals)); })
      .def_property_readonly(
          "weights", [](const kernels::SampleBatch& b) { return py::array(py::cast(b.weights)); })
      .def("folded", &kernels::fold_duplicate_samples,
           "The same samples with identical transitions merged into one of summed weight, in "
           "order of first occurrence (what a job's lspi.fold_duplicates does).");

  py::class_<LspiFit>(module, "LspiFit", R"(The result of ggk.lspi.

Calling it is the greedy policy: fit(k) for one state's row (a copy basis: its p
state kernels; another basis: its m feature rows phi(s, 0) .. phi(s, m - 1)) gives
the action, fit(K) for many rows (2-D array or scipy.sparse) an array of actions;
ties go to the lowest action.)")
      .def_property_readonly("status",
                             [](const LspiFit& f) { return kernels::to_string(f.result.status); })
      .def_property_readonly("ok", [](const LspiFit& f) { return f.result.ok(); })
      .def_property_readonly("message", [](const LspiFit& f) { return f.result.message; })
      .def_property_readonly("iterations", [](const LspiFit& f) { return f.result.iterations(); })
      .def_property_readonly("num_actions", [](const LspiFit& f) { return f.num_actions; })
      .def_property_readonly(
          "weights", [](const LspiFit& f) { return f.result.weights; },
          "w of the last successful evaluation (empty if none)")
      .def_property_readonly(
          "policy", [](const LspiFit& f) { return py::array(py::cast(f.result.policy)); },
          "The greedy action of every basis state")
      .def_property_readonly(
          "history",
          [](const LspiFit& f) {
            const auto column = [&](auto member) {
              py::list values;
              for (const kernels::LspiIteration& it : f.result.history) values.append(it.*member);
              return py::module_::import("numpy").attr("asarray")(values);
            };
            py::dict history;
            history["policy_changes"] = column(&kernels::LspiIteration::policy_changes);
            history["weight_change"] = column(&kernels::LspiIteration::weight_change);
            history["relative_residual"] = column(&kernels::LspiIteration::relative_residual);
            history["rcond"] = column(&kernels::LspiIteration::rcond);
            history["dense_solve"] = column(&kernels::LspiIteration::dense_solve);
            return history;
          },
          "Per evaluation: policy_changes, weight_change, relative_residual, rcond, dense_solve")
      .def_property_readonly("iterates",
                             [](const LspiFit& f) { return py::cast(f.result.iterates); })
      .def_property_readonly(
          "A", [](const LspiFit& f) { return to_scipy_csc(kernels::SparseColMatrix(f.result.a)); },
          "The last evaluation's system (BRM: the lower triangle only)")
      .def_property_readonly("b", [](const LspiFit& f) { return f.result.b; })
      .def("q_values", &action_values, py::arg("rows"),
           "Q(s, a) of the states the rows describe (one row per state and action column)")
      .def("__call__", &greedy_actions, py::arg("rows"))
      .def("__repr__", [](const LspiFit& f) {
        return "<ggk.LspiFit " + std::string(kernels::to_string(f.result.status)) + " after " +
               std::to_string(f.result.iterations()) + " iterations, " +
               std::to_string(f.result.weights.size()) + " weights>";
      });

  module.def(
      "lspi",
      [](const py::handle& samples, const StateActionBasis& basis, const std::string& solver,
         double gamma, double ridge, const std::string& ridge_scale, std::int32_t max_iterations,
         const std::string& stopping, double weight_tolerance, const std::string& linear_algebra,
         double min_rcond, bool keep_iterates) {
        const kernels::SampleBatch batch = batch_from(samples);
        const kernels::LspiOptions options =
            lspi_options(solver, gamma, ridge, ridge_scale, max_iterations, stopping,
                         weight_tolerance, linear_algebra, min_rcond, keep_iterates);
        LspiFit fit;
        fit.scheme = basis.scheme;
        fit.num_actions = basis.num_actions;
        fit.row_width = basis.is_copy() ? basis.state_kernels.cols() : basis.table.cols();
        py::gil_scoped_release release;
        fit.result = basis.is_copy()
                         ? kernels::fit_lspi_copy_basis(basis.state_kernels, basis.num_actions,
                                                        batch, options)
                         : kernels::fit_lspi(basis.table, basis.num_actions, batch, options);
        return fit;
      },
      py::arg("samples"), py::arg("basis"), py::arg("solver") = "brm", py::arg("gamma") = 0.9,
      py::arg("ridge") = 0.0, py::arg("ridge_scale") = "absolute", py::arg("max_iterations") = 20,
      py::arg("stopping") = "policy", py::arg("weight_tolerance") = 1e-5,
      py::arg("linear_algebra") = "auto", py::arg("min_rcond") = 1e-14,
      py::arg("keep_iterates") = false,
      R"(Least-squares policy iteration (Lagoudakis & Parr 2003) as the engine fits it.

samples: ggk.Samples or a dict of its arrays; basis: ggk.copy_basis, shift_basis
or table_basis. solver "brm" (Bellman residual minimisation) or "lstdq"; ridge
lambda added to A ("absolute", or "relative": lambda times A's mean absolute
diagonal); stopping "policy" (no sample state's greedy action changes) or
"weights" (||w_k - w_k-1|| <= weight_tolerance), at most max_iterations
evaluations; linear_algebra "auto", "sparse" (CHOLMOD / UMFPACK) or "dense"
(LAPACK); a system with a reciprocal condition estimate below min_rcond fails the
fit (status "solver_failed", message why). The same weights, bit for bit, as the
engine's fit of the same samples and basis. The GIL is released while it runs.)");
}

}  // namespace ggk::python
