#include "kernels/lspi.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include "kernels/action_block_system.hpp"

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

namespace {

// A as CHOLMOD / UMFPACK take it: compressed columns, the lower triangle only when
// `triangle` is lower (BRM), ridge added to the diagonal. The diagonal is always
// structurally present, even for ridge = 0: CHOLMOD needs it, and a stable pattern
// lets the symbolic analysis be reused. Other exact zeros are left out.
enum class Triangle { lower, full };

SparseColMatrix compress_system(const Eigen::MatrixXd& dense, Triangle triangle, double ridge) {
  const Eigen::Index k = dense.cols();
  SparseColMatrix a(k, k);
  std::int64_t nnz = 0;
  for (Eigen::Index col = 0; col < k; ++col) {
    for (Eigen::Index row = triangle == Triangle::lower ? col : 0; row < k; ++row) {
      nnz += (dense(row, col) != 0.0 || row == col) ? 1 : 0;
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
  return a;
}

void check_inputs(const SparseRowMatrix& features, std::int32_t num_actions,
                  const SampleBatch& samples, const LspiOptions& options) {
  if (num_actions <= 0) throw std::invalid_argument("fit_lspi: num_actions must be > 0");
  if (features.rows() % num_actions != 0) {
    throw std::invalid_argument("fit_lspi: feature table has " + std::to_string(features.rows()) +
                                " rows, not a multiple of " + std::to_string(num_actions) +
                                " actions");
  }
  if (!(options.gamma >= 0.0 && options.gamma < 1.0)) {
    throw std::invalid_argument("fit_lspi: gamma must be in [0, 1)");
  }
  if (!(options.ridge >= 0.0) || !std::isfinite(options.ridge)) {
    throw std::invalid_argument("fit_lspi: ridge must be finite and >= 0");
  }
  if (options.max_iterations < 1) throw std::invalid_argument("fit_lspi: max_iterations < 1");
  samples.validate(static_cast<std::int32_t>(features.rows() / num_actions), num_actions);
  const std::string violation = action_block_violation(features, num_actions);
  if (!violation.empty()) {
    throw std::invalid_argument("fit_lspi: features are not in action-block form: " + violation);
  }
}

}  // namespace

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

LspiResult fit_lspi(const SparseRowMatrix& features, std::int32_t num_actions,
                    const SampleBatch& samples, const LspiOptions& options) {
  check_inputs(features, num_actions, samples, options);
  const std::size_t n = samples.size();
  const auto num_states = static_cast<std::size_t>(features.rows() / num_actions);
  const bool brm = options.solver == LspiSolver::brm;

  const ActionBlockSystem system(features, num_actions, samples, options.solver, options.gamma);
  SymmetricSolver symmetric(options.solver_settings);
  NonsymmetricSolver nonsymmetric(options.solver_settings);

  // The states whose greedy action matters to the fit: those the samples start
  // from or bootstrap from. Elsewhere (e.g. goal states only entered terminally)
  // Q is not constrained by data and its argmax may flip between near-equal values.
  std::vector<std::uint8_t> on_samples(num_states, 0);
  for (std::size_t i = 0; i < n; ++i) {
    on_samples[static_cast<std::size_t>(samples.states[i])] = 1;
    if (!samples.terminals[i]) on_samples[static_cast<std::size_t>(samples.next_states[i])] = 1;
  }

  LspiResult result;
  std::vector<std::int32_t> policy(num_states, 0);  // greedy for w = 0
  Eigen::MatrixXd dense_a;
  for (std::int32_t iteration = 1; iteration <= options.max_iterations; ++iteration) {
    Eigen::VectorXd b;
    system.assemble(policy, dense_a, b);
    SparseColMatrix a =
        compress_system(dense_a, brm ? Triangle::lower : Triangle::full, options.ridge);

    Eigen::VectorXd w;
    const SolveReport report = brm ? symmetric.solve(a, b, w) : nonsymmetric.solve(a, b, w);
    if (!report.ok) {
      result.status = LspiStatus::solver_failed;
      result.message = "policy evaluation " + std::to_string(iteration) + " (" +
                       to_string(options.solver) + "): " + report.message;
      return result;
    }

    std::vector<std::int32_t> improved = greedy_policy(features, num_actions, w);
    std::int32_t changes = 0;
    for (std::size_t s = 0; s < num_states; ++s) {
      changes += (on_samples[s] && improved[s] != policy[s]) ? 1 : 0;
    }
    result.history.push_back(
        {changes, report.relative_residual, report.rcond, report.reused_analysis});
    result.weights = std::move(w);
    result.policy = improved;
    result.a = std::move(a);
    result.b = std::move(b);
    policy = std::move(improved);
    if (changes == 0) {
      result.status = LspiStatus::converged;
      return result;
    }
  }
  result.status = LspiStatus::max_iterations;
  return result;
}

}  // namespace ggk::kernels
