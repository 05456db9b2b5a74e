#include "kernels/action_block_system.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>
#include <utility>

#include "kernels/blas_runtime.hpp"
#include "kernels/flop_count.hpp"

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

// Its fields are named as ActionBlockSystem's were before they were shared, so
// that gather and weighted_rewards read as they did.
class ActionBlockFixed {
 public:
  // copy_rows: features holds state kernels (p columns), kappa(s, a) its row s, or
  // its row row_of_pair[s m + a] where row_of_pair is not empty; else features is
  // the table and kappa(s, a) its row s m + a, in block a.
  // start_samples: the samples D_a and the start right-hand side are formed from
  // (null: `samples`; pooled_copy_samples.hpp's by_start).
  ActionBlockFixed(const SparseRowMatrix& features, bool copy_rows,
                   std::span<const std::int32_t> row_of_pair, std::int32_t num_actions,
                   const SampleBatch& samples, const SampleBatch* start_samples = nullptr);

  // The row of features_ that holds kappa(state, action).
  Eigen::Index table_row(std::int64_t state, std::int32_t action) const {
    if (!row_of_pair_.empty()) {
      return row_of_pair_[static_cast<std::size_t>(state * num_actions_ + action)];
    }
    return copy_rows_ ? state : state * num_actions_ + action;
  }

  // Row r of the result (a rows.size() x p view of `buffer`, grown as needed) is
  // sqrt(w_i) kappa(s, action) for sample i = rows[r], s its start (next_state =
  // false) or successor state.
  Eigen::Map<Eigen::MatrixXd> gather(const std::vector<std::int32_t>& rows, bool next_state,
                                     std::int32_t action, std::vector<double>& buffer) const;
  // sqrt(w_i) r_i for sample i = rows[r] (a view of `buffer`).
  Eigen::Map<Eigen::VectorXd> weighted_rewards(const std::vector<std::int32_t>& rows,
                                               std::vector<double>& buffer) const;

  const SparseRowMatrix& features_;
  bool copy_rows_;
  std::span<const std::int32_t> row_of_pair_;
  const SampleBatch& samples_;
  std::int32_t num_actions_;
  Eigen::Index p_;
  std::vector<double> sqrt_weights_;
  std::vector<Eigen::MatrixXd> start_blocks_;
  Eigen::VectorXd start_rhs_;
  std::int64_t live_samples_ = 0;
  bool table_has_zeros_ = false;
  bool gathered_without_zeros_ = false;
  // kappa(s, a) is the same row for every a (the copy basis from its kernels).
  bool bootstrap_free_ = false;
};

ActionBlockFixed::ActionBlockFixed(const SparseRowMatrix& features, bool copy_rows,
                                   std::span<const std::int32_t> row_of_pair,
                                   std::int32_t num_actions, const SampleBatch& samples,
                                   const SampleBatch* start_samples)
    : features_(features),
      copy_rows_(copy_rows),
      row_of_pair_(row_of_pair),
      samples_(samples),
      num_actions_(num_actions),
      p_(copy_rows ? features.cols() : features.cols() / num_actions),
      sqrt_weights_(samples.size()),
      start_rhs_(Eigen::VectorXd::Zero(p_ * num_actions)) {
  std::vector<double> u_buffer, reward_buffer;
  use_calling_thread_blas();
  // A copy table read as a table is one too: the same rows for every action.
  bootstrap_free_ = copy_rows || is_copy_layout(features, num_actions);
  const auto m = static_cast<std::size_t>(num_actions);
  for (std::size_t pair = 0; pair < row_of_pair.size() && bootstrap_free_; ++pair) {
    bootstrap_free_ = row_of_pair[pair] == row_of_pair[pair - pair % m];
  }
  std::vector<std::vector<std::int32_t>> by_action(static_cast<std::size_t>(num_actions));
  for (std::size_t i = 0; i < samples.size(); ++i) {
    sqrt_weights_[i] = std::sqrt(samples.weights[i]);
    by_action[static_cast<std::size_t>(samples.actions[i])].push_back(static_cast<std::int32_t>(i));
  }
  for (std::size_t i = 0; i < samples.size(); ++i) live_samples_ += samples.terminals[i] ? 0 : 1;
  // What the table holds: the rows of features it is made of (with shared rows,
  // those some pair reads; every row otherwise).
  std::vector<std::uint8_t> in_table(static_cast<std::size_t>(features.rows()),
                                     row_of_pair.empty() ? 1 : 0);
  for (const std::int32_t row : row_of_pair) in_table[static_cast<std::size_t>(row)] = 1;
  for (Eigen::Index row = 0; row < features.rows() && !table_has_zeros_; ++row) {
    if (!in_table[static_cast<std::size_t>(row)]) continue;
    Eigen::Index nonzeros = 0;
    for (SparseRowMatrix::InnerIterator it(features, row); it; ++it) {
      nonzeros += it.value() != 0.0 ? 1 : 0;
    }
    table_has_zeros_ = nonzeros != p_;
  }
  // Every gathered entry sqrt(w_i) kappa is non-zero when the table has no zero
  // and the smallest product of a weight's root and a value's magnitude does not
  // underflow (rounding is monotonic: no other product is smaller).
  if (!table_has_zeros_) {
    double smallest_value = std::numeric_limits<double>::infinity();
    for (Eigen::Index row = 0; row < features.rows(); ++row) {
      if (!in_table[static_cast<std::size_t>(row)]) continue;
      for (SparseRowMatrix::InnerIterator it(features, row); it; ++it) {
        smallest_value = std::min(smallest_value, std::abs(it.value()));
      }
    }
    double smallest_root = std::numeric_limits<double>::infinity();
    for (const double root : sqrt_weights_) smallest_root = std::min(smallest_root, root);
    gathered_without_zeros_ = smallest_value * smallest_root > 0.0;
  }
  if (start_samples != nullptr) {
    ActionBlockFixed start(features, copy_rows, row_of_pair, num_actions, *start_samples);
    start_blocks_ = std::move(start.start_blocks_);
    start_rhs_ = std::move(start.start_rhs_);
    return;
  }
  start_blocks_.reserve(by_action.size());
  for (std::int32_t a = 0; a < num_actions; ++a) {
    const std::vector<std::int32_t>& rows = by_action[static_cast<std::size_t>(a)];
    const auto u = gather(rows, false, a, u_buffer);
    Eigen::MatrixXd lower = Eigen::MatrixXd::Zero(p_, p_);
    lower.selfadjointView<Eigen::Lower>().rankUpdate(u.transpose());
    // The rank update and the right-hand side's product.
    const auto p = static_cast<double>(p_);
    count_flops(static_cast<double>(u.rows()) * (p * (p + 1.0) + 2.0 * p));
    start_blocks_.emplace_back(lower.selfadjointView<Eigen::Lower>());
    start_rhs_.segment(a * p_, p_).noalias() =
        u.transpose() * weighted_rewards(rows, reward_buffer);
  }
}

ActionBlockSystem::ActionBlockSystem(const SparseRowMatrix& features, std::int32_t num_actions,
                                     const SampleBatch& samples, LspiSolver solver, double gamma)
    : ActionBlockSystem(std::make_shared<const ActionBlockFixed>(
                            features, false, std::span<const std::int32_t>(), num_actions, samples),
                        solver, gamma) {}

ActionBlockSystem::ActionBlockSystem(SharedRowsTag, const SparseRowMatrix& kernels,
                                     std::span<const std::int32_t> row_of_pair,
                                     std::int32_t num_actions, const SampleBatch& samples,
                                     LspiSolver solver, double gamma)
    : ActionBlockSystem(std::make_shared<const ActionBlockFixed>(kernels, true, row_of_pair,
                                                                 num_actions, samples),
                        solver, gamma) {}

ActionBlockSystem::ActionBlockSystem(CopyBasisTag, const SparseRowMatrix& state_kernels,
                                     std::int32_t num_actions, const SampleBatch& samples,
                                     LspiSolver solver, double gamma,
                                     std::shared_ptr<const ActionBlockFixed> shared)
    : ActionBlockSystem(
          shared ? std::move(shared)
                 : std::make_shared<const ActionBlockFixed>(
                       state_kernels, true, std::span<const std::int32_t>(), num_actions, samples),
          solver, gamma) {
  if (&features_ != &state_kernels || &samples_ != &samples || num_actions_ != num_actions ||
      !copy_rows_ || !fixed_->row_of_pair_.empty()) {
    throw std::invalid_argument(
        "ActionBlockSystem: the shared fixed part was made for other state kernels, samples or "
        "actions");
  }
}

std::shared_ptr<const ActionBlockFixed> ActionBlockSystem::copy_basis_fixed(
    const SparseRowMatrix& state_kernels, std::int32_t num_actions, const SampleBatch& samples,
    const SampleBatch* start_samples) {
  if (!state_kernels.isCompressed()) {
    throw std::invalid_argument(
        "ActionBlockSystem::copy_basis_fixed: the kernels are not compressed");
  }
  if (num_actions < 1) {
    throw std::invalid_argument(
        "ActionBlockSystem::copy_basis_fixed: " + std::to_string(num_actions) + " actions");
  }
  samples.validate(static_cast<std::int32_t>(state_kernels.rows()), num_actions);
  if (start_samples != nullptr) {
    start_samples->validate(static_cast<std::int32_t>(state_kernels.rows()), num_actions);
  }
  return std::make_shared<const ActionBlockFixed>(
      state_kernels, true, std::span<const std::int32_t>(), num_actions, samples, start_samples);
}

ActionBlockSystem::ActionBlockSystem(std::shared_ptr<const ActionBlockFixed> fixed,
                                     LspiSolver solver, double gamma)
    : fixed_(std::move(fixed)),
      features_(fixed_->features_),
      copy_rows_(fixed_->copy_rows_),
      samples_(fixed_->samples_),
      num_actions_(fixed_->num_actions_),
      p_(fixed_->p_),
      k_(p_ * num_actions_),
      solver_(solver),
      gamma_(gamma),
      start_blocks_(fixed_->start_blocks_),
      start_rhs_(fixed_->start_rhs_),
      live_samples_(fixed_->live_samples_),
      table_has_zeros_(fixed_->table_has_zeros_),
      gathered_without_zeros_(fixed_->gathered_without_zeros_),
      bootstrap_free_(fixed_->bootstrap_free_) {
  use_calling_thread_blas();
}

Eigen::Map<Eigen::MatrixXd> ActionBlockSystem::gather(const std::vector<std::int32_t>& rows,
                                                      bool next_state, std::int32_t action,
                                                      std::vector<double>& buffer) const {
  return fixed_->gather(rows, next_state, action, buffer);
}

Eigen::Map<Eigen::VectorXd> ActionBlockSystem::weighted_rewards(
    const std::vector<std::int32_t>& rows, std::vector<double>& buffer) const {
  return fixed_->weighted_rewards(rows, buffer);
}

Eigen::Map<Eigen::MatrixXd> ActionBlockFixed::gather(const std::vector<std::int32_t>& rows,
                                                     bool next_state, std::int32_t action,
                                                     std::vector<double>& buffer) const {
  const auto n = static_cast<Eigen::Index>(rows.size());
  const auto size = rows.size() * static_cast<std::size_t>(p_);
  if (buffer.size() < size) buffer.resize(size);
  double* out = buffer.data();
  const Eigen::Index offset = copy_rows_ ? 0 : action * p_;
  const auto* outer = features_.outerIndexPtr();
  const auto* row_sizes = features_.innerNonZeroPtr();  // null when compressed
  const auto* inner = features_.innerIndexPtr();
  const double* values = features_.valuePtr();
  // Eight rows at a time (one cache line of each column of `out`). A row with
  // all p entries holds columns offset .. offset + p - 1 in order (action-block
  // form), so it is copied column by column; other rows are zeroed, then
  // scattered. Either way out(r, c) = sqrt(w_i) kappa_c, the same product.
  constexpr Eigen::Index kBlock = 8;
  std::int64_t begin[kBlock], end[kBlock];
  double scale[kBlock];
  for (Eigen::Index r0 = 0; r0 < n; r0 += kBlock) {
    const Eigen::Index count = std::min(kBlock, n - r0);
    bool dense = true;
    for (Eigen::Index b = 0; b < count; ++b) {
      const auto i = static_cast<std::size_t>(rows[static_cast<std::size_t>(r0 + b)]);
      const std::int64_t state = next_state ? samples_.next_states[i] : samples_.states[i];
      const Eigen::Index table_row = this->table_row(state, action);
      begin[b] = outer[table_row];
      end[b] = row_sizes ? begin[b] + row_sizes[table_row] : outer[table_row + 1];
      scale[b] = sqrt_weights_[i];
      dense = dense && end[b] - begin[b] == p_;
    }
    if (dense) {
      for (Eigen::Index c = 0; c < p_; ++c) {
        double* column = out + c * n + r0;
        for (Eigen::Index b = 0; b < count; ++b) column[b] = scale[b] * values[begin[b] + c];
      }
      continue;
    }
    for (Eigen::Index c = 0; c < p_; ++c) {
      std::fill(out + c * n + r0, out + c * n + r0 + count, 0.0);
    }
    for (Eigen::Index b = 0; b < count; ++b) {
      for (auto e = begin[b]; e < end[b]; ++e) {
        out[(inner[e] - offset) * n + r0 + b] = scale[b] * values[e];
      }
    }
  }
  return Eigen::Map<Eigen::MatrixXd>(out, n, p_);
}

Eigen::Map<Eigen::VectorXd> ActionBlockFixed::weighted_rewards(
    const std::vector<std::int32_t>& rows, std::vector<double>& buffer) const {
  if (buffer.size() < rows.size()) buffer.resize(rows.size());
  Eigen::Map<Eigen::VectorXd> out(buffer.data(), static_cast<Eigen::Index>(rows.size()));
  for (std::size_t r = 0; r < rows.size(); ++r) {
    const auto i = static_cast<std::size_t>(rows[r]);
    out(static_cast<Eigen::Index>(r)) = sqrt_weights_[i] * samples_.rewards[i];
  }
  return out;
}

std::vector<std::vector<std::int32_t>> ActionBlockSystem::full_groups(
    const std::vector<std::int32_t>& policy) const {
  const auto m = static_cast<std::size_t>(num_actions_);
  std::vector<std::vector<std::int32_t>> groups(m * m);
  for (std::size_t i = 0; i < samples_.size(); ++i) {
    if (samples_.terminals[i]) continue;
    const auto next =
        static_cast<std::size_t>(policy[static_cast<std::size_t>(samples_.next_states[i])]);
    groups[static_cast<std::size_t>(samples_.actions[i]) * m + next].push_back(
        static_cast<std::int32_t>(i));
  }
  return groups;
}

void ActionBlockSystem::reset(PolicyBlocks& blocks, bool supports) const {
  const auto m = static_cast<std::size_t>(num_actions_);
  const bool brm = solver_ == LspiSolver::brm;
  blocks.cross.assign(m * m, Eigen::MatrixXd::Zero(p_, p_));
  if (brm) blocks.next.assign(m, Eigen::MatrixXd::Zero(p_, p_));
  blocks.rhs = start_rhs_;
  blocks.group_sizes.assign(m * m, 0);
  const bool block_supports = supports && table_has_zeros_;
  blocks.cross_support.assign(block_supports ? m * m : 0, Eigen::MatrixXd::Zero(p_, p_));
  blocks.next_support.assign(block_supports && brm ? m : 0, Eigen::MatrixXd::Zero(p_, p_));
  blocks.rhs_support = supports && brm ? Eigen::VectorXd::Zero(k_) : Eigen::VectorXd();
}

namespace {

// The 0/1 indicator of values != 0 (a view of `buffer`, grown as needed).
Eigen::Map<Eigen::MatrixXd> nonzero_indicator(const Eigen::Ref<const Eigen::MatrixXd>& values,
                                              std::vector<double>& buffer) {
  const auto size = static_cast<std::size_t>(values.size());
  if (buffer.size() < size) buffer.resize(size);
  Eigen::Map<Eigen::MatrixXd> out(buffer.data(), values.rows(), values.cols());
  out = (values.array() != 0.0).cast<double>();
  return out;
}

// Sets entries of `values` whose count in `support` is zero to exactly zero (the
// lower triangle only when `lower`).
void reset_unsupported(const Eigen::MatrixXd& support, bool lower, Eigen::MatrixXd& values) {
  for (Eigen::Index col = 0; col < values.cols(); ++col) {
    for (Eigen::Index row = lower ? col : 0; row < values.rows(); ++row) {
      if (support(row, col) == 0.0) values(row, col) = 0.0;
    }
  }
}

}  // namespace

void ActionBlockSystem::accumulate(const std::vector<std::vector<std::int32_t>>& groups,
                                   double sign, PolicyBlocks& blocks, Scratch& scratch,
                                   const DerivedBlocks* derived) const {
  const auto m = static_cast<std::size_t>(num_actions_);
  const bool brm = solver_ == LspiSolver::brm;
  const bool block_supports = !blocks.cross_support.empty();
  const bool rhs_supports = blocks.rhs_support.size() != 0;
  std::vector<std::uint8_t> touched(m * m, 0);
  for (std::size_t g = 0; g < groups.size(); ++g) {
    const std::vector<std::int32_t>& rows = groups[g];
    if (rows.empty()) continue;
    touched[g] = 1;
    const auto x = static_cast<std::int32_t>(g / m), y = static_cast<std::int32_t>(g % m);
    // Blocks a rebuild by subtraction forms afterwards (subtract_from_totals).
    const bool cross_derived =
        derived != nullptr && derived->cross[static_cast<std::size_t>(x)] == y;
    const bool next_derived = derived != nullptr && derived->next == y;
    blocks.group_sizes[g] +=
        static_cast<std::int64_t>(sign) * static_cast<std::int64_t>(rows.size());
    if (cross_derived && !brm) continue;  // LSTD-Q: the group's C is all it adds
    const auto v = gather(rows, true, y, scratch.v);
    const double n = static_cast<double>(rows.size()), p = static_cast<double>(p_);
    // The indicator of v's non-zeros, formed once for the counts that need it.
    bool v_support_formed = false;
    const auto v_support = [&] {
      if (!v_support_formed) nonzero_indicator(v, scratch.v_support);
      v_support_formed = true;
      return Eigen::Map<Eigen::MatrixXd>(scratch.v_support.data(), v.rows(), p_);
    };
    if (!cross_derived) {
      const auto u = gather(rows, false, x, scratch.u);
      if (blocks.group_sizes[g] == 0) {
        blocks.cross[g].setZero();  // the sum over an empty group: exact zeros
      } else if (sign > 0) {
        blocks.cross[g].noalias() += u.transpose() * v;  // C_xy
      } else {
        blocks.cross[g].noalias() -= u.transpose() * v;
      }
      if (blocks.group_sizes[g] != 0) count_flops(2.0 * n * p * p);
      // The counts: the same products on the indicators of the non-zeros (exact
      // integers in doubles).
      if (block_supports) {
        const auto u_support = nonzero_indicator(u, scratch.u_support);
        blocks.cross_support[g].noalias() += sign * (u_support.transpose() * v_support());
        count_flops(2.0 * n * p * p);
      }
    }
    if (block_supports && brm && !next_derived) {
      blocks.next_support[static_cast<std::size_t>(y)].selfadjointView<Eigen::Lower>().rankUpdate(
          v_support().transpose(), sign);
      count_flops(n * p * (p + 1.0));
    }
    if (!brm) continue;
    if (!next_derived) {
      blocks.next[static_cast<std::size_t>(y)].selfadjointView<Eigen::Lower>().rankUpdate(
          v.transpose(), sign * gamma_ * gamma_);
      count_flops(n * p * (p + 1.0));
    }
    const auto rewards = weighted_rewards(rows, scratch.rewards);
    blocks.rhs.segment(y * p_, p_).noalias() -= (sign * gamma_) * (v.transpose() * rewards);
    count_flops(2.0 * n * p);
    if (rhs_supports && gathered_without_zeros_) {
      // Every v entry is non-zero: each entry's count is the group's number of
      // non-zero rewards (the same exact integer as the product below gives).
      double nonzero_rewards = 0.0;
      for (Eigen::Index r = 0; r < rewards.size(); ++r) nonzero_rewards += rewards(r) != 0.0;
      blocks.rhs_support.segment(y * p_, p_).array() += sign * nonzero_rewards;
    } else if (rhs_supports) {
      blocks.rhs_support.segment(y * p_, p_).noalias() +=
          sign * (v_support().transpose() * nonzero_indicator(rewards, scratch.reward_support));
      count_flops(2.0 * n * p);
    }
  }
  if (sign < 0 && block_supports) {
    // A removal leaves rounding residue where no remaining sample reaches: reset.
    std::vector<std::uint8_t> next_touched(m, 0);
    for (std::size_t g = 0; g < m * m; ++g) {
      if (!touched[g]) continue;
      reset_unsupported(blocks.cross_support[g], false, blocks.cross[g]);
      next_touched[g % m] = 1;
    }
    for (std::size_t y = 0; brm && y < m; ++y) {
      if (next_touched[y]) reset_unsupported(blocks.next_support[y], true, blocks.next[y]);
    }
  }
  if (!brm) return;
  if (sign < 0 && rhs_supports) {
    for (Eigen::Index e = 0; e < k_; ++e) {
      if (blocks.rhs_support(e) == 0.0) blocks.rhs(e) = start_rhs_(e);
    }
  }
  // E_y is an empty sum once no group (x, y) holds a sample.
  for (std::size_t y = 0; y < m; ++y) {
    std::int64_t size = 0;
    for (std::size_t x = 0; x < m; ++x) size += blocks.group_sizes[x * m + y];
    if (size != 0) continue;
    blocks.next[y].setZero();
    blocks.rhs.segment(static_cast<Eigen::Index>(y) * p_, p_) =
        start_rhs_.segment(static_cast<Eigen::Index>(y) * p_, p_);
  }
}

ActionBlockSystem::GroupTotals ActionBlockSystem::group_totals(const PolicyBlocks& blocks) const {
  const auto m = static_cast<std::size_t>(num_actions_);
  GroupTotals totals;
  // The sum of the m blocks per_block[first .. first + m).
  const auto sum_of_m = [&](const std::vector<Eigen::MatrixXd>& per_block, std::size_t first) {
    Eigen::MatrixXd sum = per_block[first];
    for (std::size_t y = 1; y < m; ++y) sum += per_block[first + y];
    return sum;
  };
  for (std::size_t x = 0; x < m; ++x) {
    totals.cross.push_back(sum_of_m(blocks.cross, x * m));
    if (!blocks.cross_support.empty()) {
      totals.cross_support.push_back(sum_of_m(blocks.cross_support, x * m));
    }
  }
  if (!blocks.next.empty()) totals.next = sum_of_m(blocks.next, 0);
  if (!blocks.next_support.empty()) totals.next_support = sum_of_m(blocks.next_support, 0);
  return totals;
}

ActionBlockSystem::DerivedBlocks ActionBlockSystem::largest_groups(
    const std::vector<std::vector<std::int32_t>>& groups) const {
  const auto m = static_cast<std::size_t>(num_actions_);
  DerivedBlocks derived;
  derived.cross.assign(m, -1);
  std::vector<std::size_t> bootstrapping(m, 0);  // samples per bootstrap action
  for (std::size_t x = 0; x < m; ++x) {
    std::size_t largest = 0;
    for (std::size_t y = 0; y < m; ++y) {
      const std::size_t size = groups[x * m + y].size();
      bootstrapping[y] += size;
      if (size > largest) {
        largest = size;
        derived.cross[x] = static_cast<std::int32_t>(y);
      }
    }
  }
  if (solver_ != LspiSolver::brm) return derived;
  std::size_t largest = 0;
  for (std::size_t y = 0; y < m; ++y) {
    if (bootstrapping[y] > largest) {
      largest = bootstrapping[y];
      derived.next = static_cast<std::int32_t>(y);
    }
  }
  return derived;
}

void ActionBlockSystem::subtract_from_totals(const DerivedBlocks& derived,
                                             PolicyBlocks& blocks) const {
  const auto m = static_cast<std::size_t>(num_actions_);
  // per_block[first + star] = total - the other m - 1 blocks of per_block[first ..
  // first + m).
  const auto total_minus_others = [&](const Eigen::MatrixXd& total,
                                      std::vector<Eigen::MatrixXd>& per_block, std::size_t first,
                                      std::size_t star) -> Eigen::MatrixXd& {
    Eigen::MatrixXd& block = per_block[first + star];
    block = total;
    for (std::size_t y = 0; y < m; ++y) {
      if (y != star) block -= per_block[first + y];
    }
    return block;
  };
  for (std::size_t x = 0; x < m; ++x) {
    if (derived.cross[x] < 0) continue;
    const auto star = static_cast<std::size_t>(derived.cross[x]);
    Eigen::MatrixXd& cross = total_minus_others(totals_.cross[x], blocks.cross, x * m, star);
    if (blocks.cross_support.empty()) continue;
    reset_unsupported(
        total_minus_others(totals_.cross_support[x], blocks.cross_support, x * m, star), false,
        cross);
  }
  if (derived.next < 0) return;
  const auto star = static_cast<std::size_t>(derived.next);
  Eigen::MatrixXd& next = total_minus_others(totals_.next, blocks.next, 0, star);
  if (blocks.next_support.empty()) return;
  reset_unsupported(total_minus_others(totals_.next_support, blocks.next_support, 0, star), true,
                    next);
}

void ActionBlockSystem::compose(const PolicyBlocks& blocks, Eigen::MatrixXd& a,
                                Eigen::VectorXd& b) const {
  const auto m = static_cast<std::size_t>(num_actions_);
  const bool brm = solver_ == LspiSolver::brm;
  a = Eigen::MatrixXd::Zero(k_, k_);
  b = blocks.rhs;
  for (std::size_t x = 0; x < m; ++x) {
    a.block(static_cast<Eigen::Index>(x) * p_, static_cast<Eigen::Index>(x) * p_, p_, p_) =
        start_blocks_[x];
  }
  // In group order, as the sums were formed before the blocks were kept: A is the
  // same bit for bit as subtracting each group's product as it is formed.
  for (std::size_t g = 0; g < m * m; ++g) {
    if (blocks.group_sizes[g] == 0) continue;
    const auto x = static_cast<Eigen::Index>(g / m), y = static_cast<Eigen::Index>(g % m);
    a.block(x * p_, y * p_, p_, p_) -= gamma_ * blocks.cross[g];
    if (brm) a.block(y * p_, x * p_, p_, p_) -= gamma_ * blocks.cross[g].transpose();
  }
  if (!brm) return;
  for (std::size_t y = 0; y < m; ++y) {
    const auto offset = static_cast<Eigen::Index>(y) * p_;
    a.block(offset, offset, p_, p_) +=
        blocks.next[y].selfadjointView<Eigen::Lower>().toDenseMatrix();
  }
}

void ActionBlockSystem::assemble(const std::vector<std::int32_t>& policy, Eigen::MatrixXd& a,
                                 Eigen::VectorXd& b) const {
  PolicyBlocks blocks;
  Scratch scratch;
  reset(blocks, false);
  accumulate(full_groups(policy), 1.0, blocks, scratch);
  compose(blocks, a, b);
}

std::int64_t ActionBlockSystem::update(const std::vector<std::int32_t>& policy, Eigen::MatrixXd& a,
                                       Eigen::VectorXd& b) {
  const auto m = static_cast<std::size_t>(num_actions_);
  const std::size_t n = samples_.size();
  std::int64_t changed = 0;
  if (!bootstrap_.empty()) {
    for (std::size_t i = 0; i < n; ++i) {
      if (samples_.terminals[i]) continue;
      const std::int32_t next = policy[static_cast<std::size_t>(samples_.next_states[i])];
      changed += next != bootstrap_[i] ? 1 : 0;
    }
  }
  last_rebuilt_ = bootstrap_.empty() || 2 * changed >= live_samples_;
  last_subtracted_ = false;
  if (last_rebuilt_) {
    reset(cached_, true);
    const std::vector<std::vector<std::int32_t>> groups = full_groups(policy);
    if (bootstrap_free_ && !bootstrap_.empty()) {
      // The sums over the bootstrap actions are known: the largest groups' blocks by
      // subtraction.
      const DerivedBlocks derived = largest_groups(groups);
      accumulate(groups, 1.0, cached_, scratch_, &derived);
      subtract_from_totals(derived, cached_);
      last_subtracted_ = true;
    } else {
      accumulate(groups, 1.0, cached_, scratch_);
      if (bootstrap_free_) totals_ = group_totals(cached_);
    }
    bootstrap_.assign(n, -1);
    for (std::size_t i = 0; i < n; ++i) {
      if (!samples_.terminals[i]) {
        bootstrap_[i] = policy[static_cast<std::size_t>(samples_.next_states[i])];
      }
    }
    compose(cached_, a, b);
    return live_samples_;
  }
  std::vector<std::vector<std::int32_t>> removed(m * m), added(m * m);
  for (std::size_t i = 0; i < n; ++i) {
    if (samples_.terminals[i]) continue;
    const std::int32_t next = policy[static_cast<std::size_t>(samples_.next_states[i])];
    if (next == bootstrap_[i]) continue;
    const auto x = static_cast<std::size_t>(samples_.actions[i]);
    removed[x * m + static_cast<std::size_t>(bootstrap_[i])].push_back(
        static_cast<std::int32_t>(i));
    added[x * m + static_cast<std::size_t>(next)].push_back(static_cast<std::int32_t>(i));
    bootstrap_[i] = next;
  }
  accumulate(removed, -1.0, cached_, scratch_);
  accumulate(added, 1.0, cached_, scratch_);
  compose(cached_, a, b);
  return changed;
}

}  // namespace ggk::kernels
