#include "kernels/lspi.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <span>
#include <stdexcept>
#include <string>
#include <utility>

#include "kernels/action_block_greedy.hpp"
#include "kernels/action_block_system.hpp"
#include "kernels/copy_basis_greedy.hpp"
#include "kernels/dense_solvers.hpp"
#include "kernels/pooled_copy_samples.hpp"
#include "kernels/shared_row_basis.hpp"

namespace ggk::kernels {

const char* to_string(LspiStatus status) {
  switch (status) {
    case LspiStatus::converged:
      return "converged";
    case LspiStatus::max_iterations:
      return "max_iterations";
    case LspiStatus::solver_failed:
      return "solver_failed";
  }
  return "unknown";
}

const char* to_string(LspiSolver solver) {
  switch (solver) {
    case LspiSolver::brm:
      return "brm";
    case LspiSolver::lstdq:
      return "lstdq";
  }
  return "unknown";
}

const char* to_string(LspiStopping stopping) {
  switch (stopping) {
    case LspiStopping::policy_unchanged:
      return "policy";
    case LspiStopping::weights_converged:
      return "weights";
  }
  return "unknown";
}

const char* to_string(LinearAlgebra kind) {
  switch (kind) {
    case LinearAlgebra::automatic:
      return "auto";
    case LinearAlgebra::sparse:
      return "sparse";
    case LinearAlgebra::dense:
      return "dense";
  }
  return "unknown";
}

const char* to_string(RidgeScale scale) {
  return scale == RidgeScale::relative ? "relative" : "absolute";
}

namespace {

// The ridge added to `system` (the evaluation's A before it), RidgeScale's rule.
double ridge_for(const Eigen::MatrixXd& system, const LspiOptions& options) {
  if (options.ridge_scale == RidgeScale::absolute || system.cols() == 0) return options.ridge;
  return options.ridge * (system.diagonal().cwiseAbs().sum() / static_cast<double>(system.cols()));
}

// A as CHOLMOD / UMFPACK take it: compressed columns, the lower triangle only when
// `triangle` is lower (BRM), ridge added to the diagonal. The diagonal is always
// structurally present, even for ridge = 0: CHOLMOD needs it, and a stable pattern
// lets the symbolic analysis be reused. Other exact zeros are left out.
enum class Triangle { lower, full };

bool kept(const Eigen::MatrixXd& dense, Eigen::Index row, Eigen::Index col) {
  return dense(row, col) != 0.0 || row == col;
}

// Writes dense's values into `a` when `a` already has the pattern compress_system
// would give it (the usual case from one policy iteration to the next); false,
// with `a` partly overwritten, when the pattern differs.
bool refill_system(const Eigen::MatrixXd& dense, Triangle triangle, double ridge,
                   SparseColMatrix& a) {
  const Eigen::Index k = dense.cols();
  if (a.rows() != k || a.cols() != k || !a.isCompressed()) return false;
  const auto* outer = a.outerIndexPtr();
  const auto* inner = a.innerIndexPtr();
  double* values = a.valuePtr();
  for (Eigen::Index col = 0; col < k; ++col) {
    auto e = outer[col];
    const auto end = outer[col + 1];
    for (Eigen::Index row = triangle == Triangle::lower ? col : 0; row < k; ++row) {
      if (!kept(dense, row, col)) continue;
      if (e == end || inner[e] != row) return false;
      values[e++] = row == col ? dense(row, col) + ridge : dense(row, col);
    }
    if (e != end) return false;
  }
  return true;
}

// Sets `a` to the compressed system, reusing its storage (no fresh pages, and
// the pattern check of the solver's analysis reuse costs one pass less).
void compress_system(const Eigen::MatrixXd& dense, Triangle triangle, double ridge,
                     SparseColMatrix& a) {
  if (refill_system(dense, triangle, ridge, a)) return;
  const Eigen::Index k = dense.cols();
  a.resize(k, k);
  std::int64_t nnz = 0;
  for (Eigen::Index col = 0; col < k; ++col) {
    for (Eigen::Index row = triangle == Triangle::lower ? col : 0; row < k; ++row) {
      nnz += kept(dense, row, col) ? 1 : 0;
    }
  }
  a.reserve(nnz);
  for (Eigen::Index col = 0; col < k; ++col) {
    a.startVec(col);
    for (Eigen::Index row = triangle == Triangle::lower ? col : 0; row < k; ++row) {
      if (row == col) {
        a.insertBack(row, col) = dense(row, col) + ridge;
      } else if (dense(row, col) != 0.0) {
        a.insertBack(row, col) = dense(row, col);
      }
    }
  }
  a.finalize();
}

// Whether the share of non-zeros among the entries the solver reads (the lower
// triangle for BRM, all for LSTD-Q; the diagonal counts, as the ridge makes it
// structurally present) reaches kDenseSystemDensity. Stops counting once it does:
// a dense system (the usual case) is read only that far.
bool dense_enough(const Eigen::MatrixXd& dense, Triangle triangle) {
  const auto k = static_cast<double>(dense.cols());
  const double read = triangle == Triangle::lower ? k * (k + 1.0) / 2.0 : k * k;
  const double needed = kDenseSystemDensity * read;
  double nonzeros = 0.0;
  for (Eigen::Index col = 0; col < dense.cols(); ++col) {
    for (Eigen::Index row = triangle == Triangle::lower ? col : 0; row < dense.rows(); ++row) {
      nonzeros += kept(dense, row, col) ? 1.0 : 0.0;
    }
    if (nonzeros >= needed) return true;
  }
  return false;
}

void check_options(std::int32_t num_actions, const LspiOptions& options) {
  if (num_actions <= 0) throw std::invalid_argument("fit_lspi: num_actions must be > 0");
  if (!(options.gamma >= 0.0 && options.gamma < 1.0)) {
    throw std::invalid_argument("fit_lspi: gamma must be in [0, 1)");
  }
  if (!(options.ridge >= 0.0) || !std::isfinite(options.ridge)) {
    throw std::invalid_argument("fit_lspi: ridge must be finite and >= 0");
  }
  if (options.max_iterations < 1) throw std::invalid_argument("fit_lspi: max_iterations < 1");
  if (!(options.weight_tolerance >= 0.0) || !std::isfinite(options.weight_tolerance)) {
    throw std::invalid_argument("fit_lspi: weight_tolerance must be finite and >= 0");
  }
}

void check_inputs(const SparseRowMatrix& features, std::int32_t num_actions,
                  const SampleBatch& samples, const LspiOptions& options) {
  check_options(num_actions, options);
  if (features.rows() % num_actions != 0) {
    throw std::invalid_argument("fit_lspi: feature table has " + std::to_string(features.rows()) +
                                " rows, not a multiple of " + std::to_string(num_actions) +
                                " actions");
  }
  samples.validate(static_cast<std::int32_t>(features.rows() / num_actions), num_actions);
  const std::string violation = action_block_violation(features, num_actions);
  if (!violation.empty()) {
    throw std::invalid_argument("fit_lspi: features are not in action-block form: " + violation);
  }
}

// True when the table is a copy basis: for every state, the rows of all actions
// hold the same entries (values, and columns shifted by a p). One pass over the
// table.
bool is_copy_layout_internal(const SparseRowMatrix& features, std::int32_t num_actions) {
  const Eigen::Index p = features.cols() / num_actions;
  const Eigen::Index states = features.rows() / num_actions;
  const auto* outer = features.outerIndexPtr();
  const auto* inner = features.innerIndexPtr();
  const double* values = features.valuePtr();
  for (Eigen::Index s = 0; s < states; ++s) {
    const Eigen::Index first = s * num_actions;
    const auto begin = outer[first], count = outer[first + 1] - outer[first];
    for (std::int32_t a = 1; a < num_actions; ++a) {
      const auto other = outer[first + a];
      if (outer[first + a + 1] - other != count) return false;
      for (std::int64_t e = 0; e < count; ++e) {
        if (inner[other + e] != inner[begin + e] + a * p ||
            !(values[other + e] == values[begin + e])) {
          return false;
        }
      }
    }
  }
  return true;
}

}  // namespace

bool is_copy_layout(const SparseRowMatrix& features, std::int32_t num_actions) {
  if (num_actions <= 0 || features.rows() % num_actions != 0 ||
      features.cols() % num_actions != 0 || !features.isCompressed()) {
    return false;
  }
  return is_copy_layout_internal(features, num_actions);
}

std::vector<std::int32_t> copy_layout_greedy_policy(const SparseRowMatrix& features,
                                                    std::int32_t num_actions,
                                                    const Eigen::VectorXd& weights) {
  if (!features.isCompressed()) return greedy_policy(features, num_actions, weights);
  return copy_greedy(features, num_actions, features.cols() / num_actions, num_actions, weights);
}

Eigen::VectorXd action_values(const SparseRowMatrix& features, const Eigen::VectorXd& weights) {
  return features * weights;
}

std::vector<std::int32_t> greedy_policy(const SparseRowMatrix& features, std::int32_t num_actions,
                                        const Eigen::VectorXd& weights) {
  const Eigen::VectorXd q = action_values(features, weights);
  const auto num_states = static_cast<std::size_t>(features.rows() / num_actions);
  std::vector<std::int32_t> policy(num_states, 0);
  for (std::size_t s = 0; s < num_states; ++s) {
    const auto base = static_cast<Eigen::Index>(s) * num_actions;
    for (std::int32_t a = 1; a < num_actions; ++a) {
      if (q(base + a) > q(base + policy[s])) policy[s] = a;
    }
  }
  return policy;
}

Eigen::VectorXd state_values(const SparseRowMatrix& features, std::int32_t num_actions,
                             const Eigen::VectorXd& weights) {
  const Eigen::VectorXd q = action_values(features, weights);
  const auto num_states = static_cast<Eigen::Index>(features.rows() / num_actions);
  Eigen::VectorXd values(num_states);
  for (Eigen::Index s = 0; s < num_states; ++s) {
    values(s) = q.segment(s * num_actions, num_actions).maxCoeff();
  }
  return values;
}

namespace {

// The states whose greedy action matters to the fit: those the samples start
// from or bootstrap from. Elsewhere (e.g. goal states only entered terminally)
// Q is not constrained by data and its argmax may flip between near-equal values.
std::vector<std::int32_t> sample_state_flags(std::size_t num_states, const SampleBatch& samples) {
  std::vector<std::int32_t> on_samples(num_states, 0);
  for (std::size_t i = 0; i < samples.size(); ++i) {
    on_samples[static_cast<std::size_t>(samples.states[i])] = 1;
    if (!samples.terminals[i]) on_samples[static_cast<std::size_t>(samples.next_states[i])] = 1;
  }
  return on_samples;
}

// `kernels` itself when compressed, else a compressed copy in `storage` (the
// greedy steps, copy_greedy and action_block_greedy, read the compressed arrays).
const SparseRowMatrix& compressed(const SparseRowMatrix& kernels, SparseRowMatrix& storage) {
  if (kernels.isCompressed()) return kernels;
  storage = kernels;
  storage.makeCompressed();
  return storage;
}

// Policy iteration over an assembled system; `greedy(w)` is the greedy policy of
// weights w over all table states. counted[s] is how many sample states table
// state s stands for (sample_state_flags when each stands for itself): a change of
// its greedy action counts that many policy changes.
template <class Greedy>
LspiResult iterate_policies(ActionBlockSystem& system, const std::vector<std::int32_t>& counted,
                            const LspiOptions& options, const Greedy& greedy) {
  const std::size_t num_states = counted.size();
  const bool brm = options.solver == LspiSolver::brm;
  SymmetricSolver symmetric(options.solver_settings);
  NonsymmetricSolver nonsymmetric(options.solver_settings);

  LspiResult result;
  std::vector<std::int32_t> policy(num_states, 0);  // greedy for w = 0
  const Triangle triangle = brm ? Triangle::lower : Triangle::full;
  DenseSymmetricSolver dense_symmetric(options.solver_settings);
  DenseLuSolver dense_lu(options.solver_settings);
  // The system being solved and the last successful one, dense or compressed;
  // swapped after each success so both keep their storage. result.a is the last
  // successful one compressed (from last_dense when it was solved densely).
  Eigen::MatrixXd dense_a, last_dense;
  SparseColMatrix a, last_a;
  bool last_was_dense = false;
  double last_ridge = options.ridge;
  auto finish = [&](LspiStatus status) {
    result.status = status;
    if (last_was_dense) {
      compress_system(last_dense, triangle, last_ridge, result.a);
    } else {
      result.a = std::move(last_a);
    }
    return std::move(result);
  };
  for (std::int32_t iteration = 1; iteration <= options.max_iterations; ++iteration) {
    Eigen::VectorXd b;
    system.update(policy, dense_a, b);
    const bool dense =
        options.linear_algebra == LinearAlgebra::dense ||
        (options.linear_algebra == LinearAlgebra::automatic && dense_enough(dense_a, triangle));

    const double ridge = ridge_for(dense_a, options);
    Eigen::VectorXd w;
    SolveReport report;
    if (dense) {
      report = brm ? dense_symmetric.solve(dense_a, ridge, b, w)
                   : dense_lu.solve(dense_a, ridge, b, w, system.block_size());
    } else {
      compress_system(dense_a, triangle, ridge, a);
      report = brm ? symmetric.solve(a, b, w) : nonsymmetric.solve(a, b, w);
    }
    if (!report.ok) {
      result.message = "policy evaluation " + std::to_string(iteration) + " (" +
                       to_string(options.solver) + "): " + report.message;
      return finish(LspiStatus::solver_failed);
    }

    std::vector<std::int32_t> improved = greedy(w);
    std::int32_t changes = 0;
    for (std::size_t s = 0; s < num_states; ++s) {
      changes += improved[s] != policy[s] ? counted[s] : 0;
    }
    const double weight_change =
        result.weights.size() == 0 ? w.norm() : (w - result.weights).norm();
    result.history.push_back({changes, weight_change, report.relative_residual, report.rcond,
                              report.reused_analysis, dense});
    if (options.keep_iterates) result.iterates.push_back(w);
    result.weights = std::move(w);
    result.policy = improved;
    if (dense) {
      dense_a.swap(last_dense);
    } else {
      a.swap(last_a);
    }
    last_was_dense = dense;
    last_ridge = ridge;
    result.b = std::move(b);
    policy = std::move(improved);
    const bool stop = options.stopping == LspiStopping::policy_unchanged
                          ? changes == 0
                          : weight_change <= options.weight_tolerance;
    if (stop) return finish(LspiStatus::converged);
  }
  return finish(LspiStatus::max_iterations);
}

}  // namespace

LspiResult fit_lspi(const SparseRowMatrix& features, std::int32_t num_actions,
                    const SampleBatch& samples, const LspiOptions& options) {
  check_inputs(features, num_actions, samples, options);
  const auto num_states = static_cast<std::size_t>(features.rows() / num_actions);
  SparseRowMatrix storage;  // both greedy steps read the compressed arrays
  const SparseRowMatrix& table = compressed(features, storage);
  // On the compressed table, whose copy layout the system can see (is_copy_layout
  // reads compressed arrays): a copy table's rebuilds subtract as the kernels' do.
  ActionBlockSystem system(table, num_actions, samples, options.solver, options.gamma);
  if (is_copy_layout(table, num_actions)) {
    const Eigen::Index p = table.cols() / num_actions;
    return iterate_policies(system, sample_state_flags(num_states, samples), options,
                            [&](const Eigen::VectorXd& w) {
                              return copy_greedy(table, num_actions, p, num_actions, w);
                            });
  }
  return iterate_policies(
      system, sample_state_flags(num_states, samples), options,
      [&](const Eigen::VectorXd& w) { return action_block_greedy(table, num_actions, w); });
}

LspiResult fit_lspi_copy_basis(const SparseRowMatrix& state_kernels, std::int32_t num_actions,
                               const SampleBatch& samples, const LspiOptions& options,
                               std::shared_ptr<const ActionBlockFixed> shared) {
  check_options(num_actions, options);
  samples.validate(static_cast<std::int32_t>(state_kernels.rows()), num_actions);
  SparseRowMatrix storage;
  const SparseRowMatrix& kernels = compressed(state_kernels, storage);
  const auto num_states = static_cast<std::size_t>(kernels.rows());
  ActionBlockSystem system(ActionBlockSystem::copy_basis_tag, kernels, num_actions, samples,
                           options.solver, options.gamma, std::move(shared));
  const Eigen::Index p = kernels.cols();
  return iterate_policies(
      system, sample_state_flags(num_states, samples), options,
      [&](const Eigen::VectorXd& w) { return copy_greedy(kernels, 1, p, num_actions, w); });
}

namespace {

// The samples of states that share kernel rows in the rows' terms (every state id
// replaced by its row), and how many sample states each row stands for; checks the
// rows (`who` names the function in the messages).
struct RowTerms {
  SampleBatch by_row;
  std::vector<std::int32_t> counted;
};

RowTerms in_row_terms(const SparseRowMatrix& row_kernels,
                      std::span<const std::int32_t> row_of_state, std::int32_t num_actions,
                      const SampleBatch& samples, const std::string& who) {
  const auto num_states = static_cast<std::int32_t>(row_of_state.size());
  if (static_cast<std::size_t>(num_states) != row_of_state.size()) {
    throw std::invalid_argument(who + ": more than 2^31 - 1 states");
  }
  samples.validate(num_states, num_actions);
  const auto rows = static_cast<std::size_t>(row_kernels.rows());
  std::vector<std::uint8_t> used(rows, 0);
  for (std::size_t s = 0; s < row_of_state.size(); ++s) {
    const std::int32_t row = row_of_state[s];
    if (row < 0 || static_cast<std::size_t>(row) >= rows) {
      throw std::invalid_argument(who + ": state " + std::to_string(s) + " has row " +
                                  std::to_string(row) + ", outside the " + std::to_string(rows) +
                                  " rows of its kernels");
    }
    used[static_cast<std::size_t>(row)] = 1;
  }
  const auto unused = std::find(used.begin(), used.end(), std::uint8_t{0});
  if (unused != used.end()) {
    throw std::invalid_argument(who + ": row " + std::to_string(unused - used.begin()) +
                                " of the kernels belongs to no state");
  }
  RowTerms terms{samples, std::vector<std::int32_t>(rows, 0)};
  for (std::int32_t& s : terms.by_row.states) s = row_of_state[static_cast<std::size_t>(s)];
  for (std::int32_t& s : terms.by_row.next_states) s = row_of_state[static_cast<std::size_t>(s)];
  const std::vector<std::int32_t> on_samples =
      sample_state_flags(static_cast<std::size_t>(num_states), samples);
  for (std::size_t s = 0; s < row_of_state.size(); ++s) {
    terms.counted[static_cast<std::size_t>(row_of_state[s])] += on_samples[s];
  }
  return terms;
}

// The result's policy per row as a policy per state.
LspiResult policy_per_state(LspiResult result, std::span<const std::int32_t> row_of_state) {
  if (!result.policy.empty()) {
    std::vector<std::int32_t> policy(row_of_state.size());
    for (std::size_t s = 0; s < row_of_state.size(); ++s) {
      policy[s] = result.policy[static_cast<std::size_t>(row_of_state[s])];
    }
    result.policy = std::move(policy);
  }
  return result;
}

}  // namespace

LspiResult fit_lspi_copy_basis(const SparseRowMatrix& row_kernels,
                               std::span<const std::int32_t> row_of_state, std::int32_t num_actions,
                               const SampleBatch& samples, const LspiOptions& options) {
  check_options(num_actions, options);
  // The samples in the rows' terms, in their order: every product and sum of the
  // system is the expanded table's, term by term.
  const RowTerms terms =
      in_row_terms(row_kernels, row_of_state, num_actions, samples, "fit_lspi_copy_basis");
  SparseRowMatrix storage;
  const SparseRowMatrix& kernels = compressed(row_kernels, storage);
  ActionBlockSystem system(ActionBlockSystem::copy_basis_tag, kernels, num_actions, terms.by_row,
                           options.solver, options.gamma);
  const Eigen::Index p = kernels.cols();
  return policy_per_state(iterate_policies(system, terms.counted, options,
                                           [&](const Eigen::VectorXd& w) {
                                             return copy_greedy(kernels, 1, p, num_actions, w);
                                           }),
                          row_of_state);
}

LspiResult fit_lspi_pooled_copy_basis(const SparseRowMatrix& row_kernels,
                                      std::span<const std::int32_t> row_of_state,
                                      std::int32_t num_actions, const SampleBatch& samples,
                                      const LspiOptions& options) {
  check_options(num_actions, options);
  const RowTerms terms =
      in_row_terms(row_kernels, row_of_state, num_actions, samples, "fit_lspi_pooled_copy_basis");
  SparseRowMatrix storage;
  const SparseRowMatrix& kernels = compressed(row_kernels, storage);
  const PooledCopySamples pooled = pool_copy_samples(kernels, num_actions, terms.by_row);
  ActionBlockSystem system(ActionBlockSystem::copy_basis_tag, pooled.table, num_actions,
                           pooled.by_successor, options.solver, options.gamma,
                           ActionBlockSystem::copy_basis_fixed(
                               pooled.table, num_actions, pooled.by_successor, &pooled.by_start));
  const Eigen::Index p = kernels.cols();
  // The greedy step reads the kernels' rows only: the pooled start vectors below
  // them are no state's, and every successor is a row of the kernels.
  return policy_per_state(iterate_policies(system, terms.counted, options,
                                           [&](const Eigen::VectorXd& w) {
                                             return copy_greedy(kernels, 1, p, num_actions, w);
                                           }),
                          row_of_state);
}

LspiResult fit_lspi_shared_rows(const SparseRowMatrix& kernels,
                                std::span<const std::int32_t> row_of_pair, std::int32_t num_actions,
                                const SampleBatch& samples, const LspiOptions& options) {
  check_options(num_actions, options);
  SparseRowMatrix storage;
  const SparseRowMatrix& compressed_kernels = compressed(kernels, storage);
  check_shared_rows(compressed_kernels, row_of_pair, num_actions, "fit_lspi_shared_rows");
  const std::size_t num_states = row_of_pair.size() / static_cast<std::size_t>(num_actions);
  if (num_states > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max())) {
    throw std::invalid_argument("fit_lspi_shared_rows: more than 2^31 - 1 states");
  }
  samples.validate(static_cast<std::int32_t>(num_states), num_actions);
  ActionBlockSystem system(ActionBlockSystem::shared_rows_tag, compressed_kernels, row_of_pair,
                           num_actions, samples, options.solver, options.gamma);
  return iterate_policies(
      system, sample_state_flags(num_states, samples), options, [&](const Eigen::VectorXd& w) {
        return shared_row_greedy(compressed_kernels, row_of_pair, num_actions, w);
      });
}

}  // namespace ggk::kernels
