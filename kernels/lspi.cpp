#include "kernels/lspi.hpp"

#include <cassert>
#include <cmath>
#include <stdexcept>
#include <string>

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

// Row i of the result is scale[i] * features.row(rows[i]); rows[i] < 0 gives a zero row.
SparseRowMatrix gather_rows(const SparseRowMatrix& features, const std::vector<std::int64_t>& rows,
                            const std::vector<double>& scale) {
  SparseRowMatrix out(static_cast<Eigen::Index>(rows.size()), features.cols());
  Eigen::Index nnz = 0;
  for (std::int64_t r : rows) {
    if (r >= 0) nnz += features.outerIndexPtr()[r + 1] - features.outerIndexPtr()[r];
  }
  out.reserve(nnz);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const auto row = static_cast<Eigen::Index>(i);
    out.startVec(row);
    if (rows[i] < 0) continue;
    for (SparseRowMatrix::InnerIterator it(features, rows[i]); it; ++it) {
      out.insertBack(row, it.col()) = scale[i] * it.value();
    }
  }
  out.finalize();
  return out;
}

// Largest k for which A is accumulated in a dense k x k buffer (32 MiB at the
// limit). Dense accumulation is ~4x faster than Eigen's sparse-sparse product for
// the LSPI sizes of the paper (k of a few hundred, tens of non-zeros per row).
constexpr Eigen::Index kDenseAssemblyLimit = 2048;

enum class Triangle { lower, full };

// Runs of at least this many contiguous columns are scattered as one vectorised
// axpy, shorter ones element by element (lspi_benchmark: untruncated k = 800 fits
// 1.5x faster than a plain loop; truncated k = 400 fits 1.8x slower than a plain
// loop, 3x slower with axpys for every run).
constexpr std::int32_t kMinVectorRun = 32;

// A = left^T right + ridge I as a compressed sparse matrix; with Triangle::lower
// only the lower triangle is formed; it requires left and right to be the same
// matrix (the symmetric BRM case). The
// diagonal is always structurally present, even for ridge = 0: CHOLMOD needs it,
// and a stable pattern lets the symbolic analysis be reused.
SparseColMatrix assemble_system(const SparseRowMatrix& left, const SparseRowMatrix& right,
                                Triangle triangle, double ridge) {
  const Eigen::Index k = left.cols();
  assert(triangle == Triangle::full || &left == &right);
  if (k > kDenseAssemblyLimit) {
    SparseColMatrix identity(k, k);
    identity.setIdentity();
    SparseColMatrix product = left.transpose() * right;
    SparseColMatrix a = triangle == Triangle::lower
                            ? SparseColMatrix(product.triangularView<Eigen::Lower>())
                            : product;
    a = a + ridge * identity;
    a.makeCompressed();
    return a;
  }
  // Row i adds the outer product left_i^T right_i: A(q, p) += left(i, q) right(i, p),
  // column p of the buffer gathers A(., p). Rows are visited in sample order, so
  // the sums are deterministic.
  // Kernel features come in contiguous runs of columns (one per action block), so
  // each scatter is done as vectorised axpys over the runs of the left row.
  Eigen::MatrixXd dense = Eigen::MatrixXd::Zero(k, k);
  std::vector<std::int32_t> run_end;  // per stored entry of the left row: end of its run
  const std::int32_t* l_index = left.innerIndexPtr();
  const double* l_value = left.valuePtr();
  for (Eigen::Index i = 0; i < left.rows(); ++i) {
    const std::int32_t l_begin = left.outerIndexPtr()[i], l_end = left.outerIndexPtr()[i + 1];
    const std::int32_t r_begin = right.outerIndexPtr()[i], r_end = right.outerIndexPtr()[i + 1];
    run_end.resize(static_cast<std::size_t>(l_end - l_begin));
    for (std::int32_t e = l_end - 1; e >= l_begin; --e) {
      const bool continues = e + 1 < l_end && l_index[e + 1] == l_index[e] + 1;
      run_end[static_cast<std::size_t>(e - l_begin)] =
          continues ? run_end[static_cast<std::size_t>(e + 1 - l_begin)] : e + 1;
    }
    for (std::int32_t rp = r_begin; rp < r_end; ++rp) {
      const std::int32_t p = right.innerIndexPtr()[rp];
      const double v = right.valuePtr()[rp];
      double* column = dense.col(p).data();
      // Lower triangle (left == right, indices sorted): rows q >= p start at rp.
      std::int32_t lq = triangle == Triangle::lower ? rp : l_begin;
      while (lq < l_end) {
        const std::int32_t end = run_end[static_cast<std::size_t>(lq - l_begin)];
        if (end - lq >= kMinVectorRun) {
          Eigen::Map<Eigen::VectorXd>(column + l_index[lq], end - lq) +=
              v * Eigen::Map<const Eigen::VectorXd>(l_value + lq, end - lq);
        } else {
          // Short runs (truncated kernels): a plain loop; a Map per run costs more.
          for (std::int32_t e = lq; e < end; ++e) column[l_index[e]] += l_value[e] * v;
        }
        lq = end;
      }
    }
  }
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

  // Phi (rows phi(s_i, a_i)) and r are fixed across iterations. BRM folds the
  // weights in as sqrt(w_i) on both Psi and r, LSTD-Q as w_i on Phi only.
  std::vector<std::int64_t> sample_rows(n);
  std::vector<double> sample_scale(n);
  Eigen::VectorXd scaled_rewards(static_cast<Eigen::Index>(n));
  for (std::size_t i = 0; i < n; ++i) {
    sample_rows[i] =
        static_cast<std::int64_t>(samples.states[i]) * num_actions + samples.actions[i];
    sample_scale[i] = brm ? std::sqrt(samples.weights[i]) : samples.weights[i];
    scaled_rewards(static_cast<Eigen::Index>(i)) =
        brm ? sample_scale[i] * samples.rewards[i] : samples.rewards[i];
  }
  const SparseRowMatrix phi = gather_rows(features, sample_rows, sample_scale);
  std::vector<double> unit_scale(n, 1.0);
  const SparseRowMatrix phi_unweighted =
      brm ? SparseRowMatrix() : gather_rows(features, sample_rows, unit_scale);
  // LSTD-Q: b = Phi^T W r is fixed.
  const Eigen::VectorXd lstdq_b =
      brm ? Eigen::VectorXd() : Eigen::VectorXd(phi.transpose() * scaled_rewards);

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
  std::vector<std::int64_t> next_rows(n);
  std::vector<double> next_scale(n);
  for (std::int32_t iteration = 1; iteration <= options.max_iterations; ++iteration) {
    // phi'_i = phi(s'_i, pi(s'_i)); terminal samples do not bootstrap.
    for (std::size_t i = 0; i < n; ++i) {
      const std::int32_t s_next = samples.next_states[i];
      next_rows[i] = samples.terminals[i]
                         ? -1
                         : static_cast<std::int64_t>(s_next) * num_actions + policy[s_next];
      next_scale[i] = options.gamma * (brm ? sample_scale[i] : 1.0);
    }
    const SparseRowMatrix phi_next = gather_rows(features, next_rows, next_scale);

    SparseColMatrix a;
    Eigen::VectorXd b;
    if (brm) {
      const SparseRowMatrix psi = phi - phi_next;  // sqrt(W) Psi
      a = assemble_system(psi, psi, Triangle::lower, options.ridge);
      b = psi.transpose() * scaled_rewards;
    } else {
      const SparseRowMatrix difference = phi_unweighted - phi_next;
      a = assemble_system(phi, difference, Triangle::full, options.ridge);
      b = lstdq_b;
    }

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
