#include "kernels/action_block_system.hpp"

#include <cmath>

#include "kernels/blas_runtime.hpp"

namespace ggk::kernels {

std::string action_block_violation(const SparseRowMatrix& features, std::int32_t num_actions) {
  if (features.cols() % num_actions != 0) {
    return "the feature table has " + std::to_string(features.cols()) +
           " columns, not a multiple of " + std::to_string(num_actions) + " actions";
  }
  const Eigen::Index p = features.cols() / num_actions;
  for (Eigen::Index row = 0; row < features.rows(); ++row) {
    const Eigen::Index action = row % num_actions;
    for (SparseRowMatrix::InnerIterator it(features, row); it; ++it) {
      if (it.col() / p != action) {
        return "row " + std::to_string(row) + " (action " + std::to_string(action) +
               ") has an entry in column " + std::to_string(it.col()) + ", outside its block [" +
               std::to_string(action * p) + ", " + std::to_string((action + 1) * p) + ")";
      }
    }
  }
  return {};
}

ActionBlockSystem::ActionBlockSystem(const SparseRowMatrix& features, std::int32_t num_actions,
                                     const SampleBatch& samples, LspiSolver solver, double gamma)
    : features_(features),
      samples_(samples),
      num_actions_(num_actions),
      p_(features.cols() / num_actions),
      solver_(solver),
      gamma_(gamma),
      sqrt_weights_(samples.size()),
      start_rhs_(Eigen::VectorXd::Zero(features.cols())) {
  use_calling_thread_blas();
  std::vector<std::vector<std::int32_t>> by_action(static_cast<std::size_t>(num_actions));
  for (std::size_t i = 0; i < samples.size(); ++i) {
    sqrt_weights_[i] = std::sqrt(samples.weights[i]);
    by_action[static_cast<std::size_t>(samples.actions[i])].push_back(static_cast<std::int32_t>(i));
  }
  start_blocks_.reserve(by_action.size());
  for (std::int32_t a = 0; a < num_actions; ++a) {
    const std::vector<std::int32_t>& rows = by_action[static_cast<std::size_t>(a)];
    const Eigen::MatrixXd u = gather(rows, false, a);
    Eigen::MatrixXd lower = Eigen::MatrixXd::Zero(p_, p_);
    lower.selfadjointView<Eigen::Lower>().rankUpdate(u.transpose());
    start_blocks_.emplace_back(lower.selfadjointView<Eigen::Lower>());
    start_rhs_.segment(a * p_, p_).noalias() = u.transpose() * weighted_rewards(rows);
  }
}

Eigen::MatrixXd ActionBlockSystem::gather(const std::vector<std::int32_t>& rows, bool next_state,
                                          std::int32_t action) const {
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(rows.size()), p_);
  const Eigen::Index offset = action * p_;
  for (std::size_t r = 0; r < rows.size(); ++r) {
    const auto i = static_cast<std::size_t>(rows[r]);
    const std::int64_t state = next_state ? samples_.next_states[i] : samples_.states[i];
    const auto table_row = static_cast<Eigen::Index>(state * num_actions_ + action);
    for (SparseRowMatrix::InnerIterator it(features_, table_row); it; ++it) {
      out(static_cast<Eigen::Index>(r), it.col() - offset) = sqrt_weights_[i] * it.value();
    }
  }
  return out;
}

Eigen::VectorXd ActionBlockSystem::weighted_rewards(const std::vector<std::int32_t>& rows) const {
  Eigen::VectorXd out(static_cast<Eigen::Index>(rows.size()));
  for (std::size_t r = 0; r < rows.size(); ++r) {
    const auto i = static_cast<std::size_t>(rows[r]);
    out(static_cast<Eigen::Index>(r)) = sqrt_weights_[i] * samples_.rewards[i];
  }
  return out;
}

void ActionBlockSystem::assemble(const std::vector<std::int32_t>& policy, Eigen::MatrixXd& a,
                                 Eigen::VectorXd& b) const {
  const auto m = static_cast<std::size_t>(num_actions_);
  const bool brm = solver_ == LspiSolver::brm;
  a = Eigen::MatrixXd::Zero(features_.cols(), features_.cols());
  b = start_rhs_;
  for (std::size_t x = 0; x < m; ++x) {
    a.block(static_cast<Eigen::Index>(x) * p_, static_cast<Eigen::Index>(x) * p_, p_, p_) =
        start_blocks_[x];
  }

  // Non-terminal samples grouped by (a_i, b_i), each group in sample order.
  std::vector<std::vector<std::int32_t>> groups(m * m);
  for (std::size_t i = 0; i < samples_.size(); ++i) {
    if (samples_.terminals[i]) continue;
    const auto next =
        static_cast<std::size_t>(policy[static_cast<std::size_t>(samples_.next_states[i])]);
    groups[static_cast<std::size_t>(samples_.actions[i]) * m + next].push_back(
        static_cast<std::int32_t>(i));
  }

  std::vector<Eigen::MatrixXd> next_blocks;  // E_b, lower triangle (BRM)
  if (brm) next_blocks.assign(m, Eigen::MatrixXd::Zero(p_, p_));
  Eigen::MatrixXd cross(p_, p_);
  for (std::size_t g = 0; g < groups.size(); ++g) {
    const std::vector<std::int32_t>& rows = groups[g];
    if (rows.empty()) continue;
    const auto x = static_cast<std::int32_t>(g / m), y = static_cast<std::int32_t>(g % m);
    const Eigen::MatrixXd u = gather(rows, false, x);
    const Eigen::MatrixXd v = gather(rows, true, y);
    cross.noalias() = u.transpose() * v;  // C_xy
    a.block(x * p_, y * p_, p_, p_) -= gamma_ * cross;
    if (!brm) continue;
    a.block(y * p_, x * p_, p_, p_) -= gamma_ * cross.transpose();
    next_blocks[static_cast<std::size_t>(y)].selfadjointView<Eigen::Lower>().rankUpdate(
        v.transpose(), gamma_ * gamma_);
    b.segment(y * p_, p_).noalias() -= gamma_ * (v.transpose() * weighted_rewards(rows));
  }
  if (!brm) return;
  for (std::size_t y = 0; y < m; ++y) {
    const auto offset = static_cast<Eigen::Index>(y) * p_;
    a.block(offset, offset, p_, p_) +=
        next_blocks[y].selfadjointView<Eigen::Lower>().toDenseMatrix();
  }
}

}  // namespace ggk::kernels
