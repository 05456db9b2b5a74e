#include "kernels/pooled_copy_samples.hpp"

#include <vector>

namespace ggk::kernels {

PooledCopySamples pool_copy_samples(const SparseRowMatrix& kernels, std::int32_t num_actions,
                                    const SampleBatch& samples) {
  const auto rows = static_cast<std::size_t>(kernels.rows());
  const Eigen::Index p = kernels.cols();
  const auto m = static_cast<std::size_t>(num_actions);
  PooledCopySamples pooled;

  // A dense index over the (row, action) pairs: rows * m is small (the pairs a
  // table of R rows can hold), a hash map would cost more than the sums.
  std::vector<std::int32_t> start_slot(rows * m, -1);
  std::vector<std::int32_t> successor_slot(rows * m, -1);
  std::vector<double> start_rewards, successor_rewards;  // sum w_i r_i, per slot
  Eigen::MatrixXd starts;  // column j: g_j = sum w_i k(u_i), grown as slots appear
  std::vector<std::int32_t> successor_of;
  std::vector<std::int32_t> action_of;
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const auto u = static_cast<std::size_t>(samples.states[i]);
    const auto a = static_cast<std::size_t>(samples.actions[i]);
    const double w = samples.weights[i];
    std::int32_t& s = start_slot[u * m + a];
    if (s < 0) {
      s = static_cast<std::int32_t>(pooled.by_start.size());
      pooled.by_start.add(samples.states[i], samples.actions[i], 0.0, samples.states[i], true, w);
      start_rewards.push_back(w * samples.rewards[i]);
    } else {
      pooled.by_start.weights[static_cast<std::size_t>(s)] += w;
      start_rewards[static_cast<std::size_t>(s)] += w * samples.rewards[i];
    }
    if (samples.terminals[i]) continue;
    const auto next = static_cast<std::size_t>(samples.next_states[i]);
    std::int32_t& t = successor_slot[next * m + a];
    if (t < 0) {
      t = static_cast<std::int32_t>(successor_of.size());
      successor_of.push_back(samples.next_states[i]);
      action_of.push_back(samples.actions[i]);
      successor_rewards.push_back(0.0);
      pooled.by_successor.weights.push_back(0.0);
      if (starts.cols() <= t) {
        starts.conservativeResize(p, std::max<Eigen::Index>(16, 2 * starts.cols()));
      }
      starts.col(t).setZero();
    }
    const auto j = static_cast<std::size_t>(t);
    pooled.by_successor.weights[j] += w;
    successor_rewards[j] += w * samples.rewards[i];
    for (SparseRowMatrix::InnerIterator it(kernels, static_cast<Eigen::Index>(u)); it; ++it) {
      starts(it.col(), t) += w * it.value();
    }
  }
  for (std::size_t s = 0; s < pooled.by_start.size(); ++s) {
    pooled.by_start.rewards[s] = start_rewards[s] / pooled.by_start.weights[s];
  }

  const std::size_t pooled_successors = successor_of.size();
  SampleBatch& by_successor = pooled.by_successor;
  by_successor.states.resize(pooled_successors);
  by_successor.actions = std::move(action_of);
  by_successor.next_states = std::move(successor_of);
  by_successor.terminals.assign(pooled_successors, 0);
  by_successor.rewards.resize(pooled_successors);
  for (std::size_t j = 0; j < pooled_successors; ++j) {
    by_successor.states[j] = static_cast<std::int32_t>(rows + j);
    by_successor.rewards[j] = successor_rewards[j] / by_successor.weights[j];
  }

  // The table: the kernels, then g_j / W_j with its exact zeros left out.
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(static_cast<std::size_t>(kernels.nonZeros()) +
                  pooled_successors * static_cast<std::size_t>(p));
  for (Eigen::Index r = 0; r < kernels.rows(); ++r) {
    for (SparseRowMatrix::InnerIterator it(kernels, r); it; ++it) {
      entries.emplace_back(r, it.col(), it.value());
    }
  }
  for (std::size_t j = 0; j < pooled_successors; ++j) {
    const auto col = static_cast<Eigen::Index>(j);
    const double weight = by_successor.weights[j];
    for (Eigen::Index c = 0; c < p; ++c) {
      const double g = starts(c, col);
      if (g != 0.0) {
        entries.emplace_back(static_cast<Eigen::Index>(rows + j), c, g / weight);
      }
    }
  }
  pooled.table.resize(static_cast<Eigen::Index>(rows + pooled_successors), p);
  pooled.table.setFromTriplets(entries.begin(), entries.end());
  pooled.table.makeCompressed();
  return pooled;
}

}  // namespace ggk::kernels
