#include "kernels/pooled_copy_samples.hpp"

#include <cmath>
#include <cstdint>
#include <limits>
#include <set>
#include <tuple>
#include <vector>

#include <gtest/gtest.h>

#include "kernels/action_block_system.hpp"
#include "kernels/lspi.hpp"
#include "kernels/random_stream.hpp"

namespace ggk::kernels {
namespace {

constexpr std::int32_t kRows = 30;
constexpr std::int32_t kActions = 3;
constexpr std::int32_t kCenters = 6;

// Kernel rows as a SOM unit's proto-value functions: signed values, some rows
// with exact zeros (`zeros`), all compressed.
SparseRowMatrix unit_rows(RandomStream& rng, bool zeros) {
  std::vector<Eigen::Triplet<double>> entries;
  for (std::int32_t r = 0; r < kRows; ++r) {
    for (std::int32_t j = 0; j < kCenters; ++j) {
      if (zeros && std::abs(r - 5 * j - 2) > 4) continue;
      entries.emplace_back(r, j, rng.uniform() - 0.4);
    }
  }
  SparseRowMatrix rows(kRows, kCenters);
  rows.setFromTriplets(entries.begin(), entries.end());
  rows.makeCompressed();
  return rows;
}

// Samples in the rows' terms, many to a (row, action) and an (action, successor):
// 2,000 samples over 30 rows and 3 actions, a tenth terminal, weights 1 .. 3.
SampleBatch row_samples(RandomStream& rng) {
  SampleBatch batch;
  for (int i = 0; i < 2000; ++i) {
    const auto u = static_cast<std::int32_t>(rng.uniform_index(kRows));
    const auto a = static_cast<std::int32_t>(rng.uniform_index(kActions));
    // Successors near the row, as a robot's next reading's unit is.
    const auto next = static_cast<std::int32_t>(
        (u + static_cast<std::int32_t>(rng.uniform_index(5)) + kRows - 2) % kRows);
    batch.add(u, a, rng.uniform() - 0.5, next, rng.uniform() < 0.1,
              1.0 + static_cast<double>(rng.uniform_index(3)));
  }
  return batch;
}

// The pooled samples: one per distinct (row, action), one per distinct (action,
// successor) of the live samples, each with the summed weight, the weighted mean
// reward and (successors) the weighted mean start vector; the table is the rows,
// then those start vectors.
TEST(PooledCopySamples, PoolTheSamplesByStartPairAndBySuccessorPair) {
  RandomStream rng(7, 0, 0);
  const SparseRowMatrix rows = unit_rows(rng, true);
  const SampleBatch samples = row_samples(rng);
  const PooledCopySamples pooled = pool_copy_samples(rows, kActions, samples);

  std::set<std::pair<std::int32_t, std::int32_t>> starts, successors;
  double total_weight = 0.0, live_weight = 0.0;
  for (std::size_t i = 0; i < samples.size(); ++i) {
    starts.insert({samples.states[i], samples.actions[i]});
    total_weight += samples.weights[i];
    if (samples.terminals[i]) continue;
    successors.insert({samples.actions[i], samples.next_states[i]});
    live_weight += samples.weights[i];
  }
  ASSERT_EQ(pooled.by_start.size(), starts.size());
  ASSERT_EQ(pooled.by_successor.size(), successors.size());
  EXPECT_LT(pooled.by_successor.size(), samples.size() / 10);
  double start_weight = 0.0, successor_weight = 0.0;
  for (const double w : pooled.by_start.weights) start_weight += w;
  for (const double w : pooled.by_successor.weights) successor_weight += w;
  EXPECT_EQ(start_weight, total_weight);  // integer weights: exact sums
  EXPECT_EQ(successor_weight, live_weight);
  ASSERT_EQ(pooled.table.rows(), kRows + static_cast<Eigen::Index>(successors.size()));
  EXPECT_EQ(Eigen::MatrixXd(pooled.table.topRows(kRows)), Eigen::MatrixXd(rows));

  // Pooled successor sample j against its samples, summed here directly.
  for (std::size_t j = 0; j < pooled.by_successor.size(); ++j) {
    const std::int32_t action = pooled.by_successor.actions[j];
    const std::int32_t next = pooled.by_successor.next_states[j];
    EXPECT_EQ(pooled.by_successor.states[j], kRows + static_cast<std::int32_t>(j));
    EXPECT_EQ(pooled.by_successor.terminals[j], 0);
    double weight = 0.0, reward = 0.0;
    Eigen::VectorXd g = Eigen::VectorXd::Zero(kCenters);
    for (std::size_t i = 0; i < samples.size(); ++i) {
      if (samples.terminals[i] || samples.actions[i] != action || samples.next_states[i] != next)
        continue;
      weight += samples.weights[i];
      reward += samples.weights[i] * samples.rewards[i];
      g += samples.weights[i] *
           Eigen::VectorXd(Eigen::MatrixXd(rows.row(samples.states[i])).transpose());
    }
    EXPECT_EQ(pooled.by_successor.weights[j], weight);
    EXPECT_NEAR(pooled.by_successor.rewards[j], reward / weight, 1e-15);
    const Eigen::VectorXd row =
        Eigen::MatrixXd(pooled.table.row(kRows + static_cast<Eigen::Index>(j))).transpose();
    EXPECT_LE((row - g / weight).cwiseAbs().maxCoeff(), 1e-14) << j;
    // An entry no sample reaches stays out of the table.
    EXPECT_EQ(((row.array() == 0.0) != (g.array() == 0.0)).count(), 0) << j;
  }
}

// The system over the pooled samples against the one over the samples (assemble,
// summed directly), for random policies over the rows, by rebuilds and rank-r
// updates, BRM and LSTD-Q, rows with and without zeros: A within rounding of its
// largest entry (the sums run in another order), exact zeros where the direct sum
// has them, b within rounding.
TEST(PooledCopySamples, SystemEqualsTheSamplesSystemUpToRounding) {
  RandomStream rng(11, 0, 0);
  const SampleBatch samples = row_samples(rng);
  for (const bool zeros : {true, false}) {
    const SparseRowMatrix rows = unit_rows(rng, zeros);
    const PooledCopySamples pooled = pool_copy_samples(rows, kActions, samples);
    for (const LspiSolver solver : {LspiSolver::brm, LspiSolver::lstdq}) {
      ActionBlockSystem direct(ActionBlockSystem::copy_basis_tag, rows, kActions, samples, solver,
                               0.9);
      ActionBlockSystem system(ActionBlockSystem::copy_basis_tag, pooled.table, kActions,
                               pooled.by_successor, solver, 0.9,
                               ActionBlockSystem::copy_basis_fixed(
                                   pooled.table, kActions, pooled.by_successor, &pooled.by_start));
      std::vector<std::int32_t> policy(kRows, 0);
      Eigen::MatrixXd a, full_a;
      Eigen::VectorXd b, full_b;
      for (int trial = 0; trial < 12; ++trial) {
        if (trial % 3 == 2) {
          policy[rng.uniform_index(kRows)] = static_cast<std::int32_t>(rng.uniform_index(kActions));
        } else {
          for (std::int32_t& action : policy) {
            action = rng.uniform() < 0.7 ? trial % kActions
                                         : static_cast<std::int32_t>(rng.uniform_index(kActions));
          }
        }
        system.update(policy, a, b);
        direct.assemble(policy, full_a, full_b);
        const double eps = std::numeric_limits<double>::epsilon();
        const double scale = full_a.cwiseAbs().maxCoeff();
        EXPECT_LE((a - full_a).cwiseAbs().maxCoeff(), 64.0 * eps * scale)
            << "trial " << trial << (zeros ? " zeros" : "");
        EXPECT_LE((b - full_b).cwiseAbs().maxCoeff(), 64.0 * eps * full_b.cwiseAbs().maxCoeff())
            << "trial " << trial;
        EXPECT_EQ(((a.array() == 0.0) != (full_a.array() == 0.0)).count(), 0) << "trial " << trial;
      }
    }
  }
}

// The pooled fit against fit_lspi_copy_basis on the same rows (states sharing
// them in blocks of five): the same status, iterations, policies per state and
// policy changes, weights within rounding, BRM and LSTD-Q; the same checks of the
// rows.
TEST(PooledCopySamples, FitEqualsTheSharedRowsFitUpToRounding) {
  RandomStream rng(5, 0, 0);
  constexpr std::int32_t kStates = 5 * kRows;
  std::vector<std::int32_t> row_of_state(kStates);
  for (std::int32_t s = 0; s < kStates; ++s) row_of_state[static_cast<std::size_t>(s)] = s / 5;
  const SparseRowMatrix rows = unit_rows(rng, true);
  SampleBatch samples;
  for (int i = 0; i < 3000; ++i) {
    const auto s = static_cast<std::int32_t>(rng.uniform_index(kStates));
    const auto a = static_cast<std::int32_t>(rng.uniform_index(kActions));
    // Action 0 moves left, the others right; reward for reaching the right end.
    const std::int32_t next = std::clamp(s + (a == 0 ? -3 : 2 + a), 0, kStates - 1);
    samples.add(s, a, next >= kStates - 10 ? 1.0 : 0.0, next, false);
  }
  for (const LspiSolver solver : {LspiSolver::brm, LspiSolver::lstdq}) {
    LspiOptions options;
    options.solver = solver;
    options.ridge = 1e-6;
    const LspiResult shared = fit_lspi_copy_basis(rows, row_of_state, kActions, samples, options);
    const LspiResult pooled =
        fit_lspi_pooled_copy_basis(rows, row_of_state, kActions, samples, options);
    ASSERT_TRUE(shared.ok());
    EXPECT_EQ(pooled.status, shared.status);
    EXPECT_EQ(pooled.policy, shared.policy);
    ASSERT_EQ(pooled.iterations(), shared.iterations());
    EXPECT_GT(shared.iterations(), 1);
    for (int i = 0; i < shared.iterations(); ++i) {
      EXPECT_EQ(pooled.history[i].policy_changes, shared.history[i].policy_changes) << i;
    }
    EXPECT_LE((pooled.weights - shared.weights).norm(), 1e-9 * shared.weights.norm());
    EXPECT_NE(pooled.weights, shared.weights);  // the sums run in another order
  }
  std::vector<std::int32_t> outside = row_of_state;
  outside[5] = kRows;
  EXPECT_THROW(fit_lspi_pooled_copy_basis(rows, outside, kActions, samples, {}),
               std::invalid_argument);
}

}  // namespace
}  // namespace ggk::kernels
