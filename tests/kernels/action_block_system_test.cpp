#include "kernels/action_block_system.hpp"

#include <string>

#include <gtest/gtest.h>

#include "kernels/random_stream.hpp"
#include "kernels/state_action_basis.hpp"
#include "kernels/transition_model.hpp"

namespace ggk::kernels {
namespace {

constexpr std::int32_t kStates = 40;
constexpr std::int32_t kActions = 3;
constexpr std::int32_t kCenters = 7;

// Random state kernels with about a third of the entries zero (as truncated kernels).
SparseRowMatrix random_state_kernels(RandomStream& rng) {
  SparseRowMatrix kernels(kStates, kCenters);
  std::vector<Eigen::Triplet<double>> entries;
  for (std::int32_t s = 0; s < kStates; ++s) {
    for (std::int32_t j = 0; j < kCenters; ++j) {
      if (rng.uniform() < 0.35) continue;
      entries.emplace_back(s, j, rng.uniform());
    }
  }
  kernels.setFromTriplets(entries.begin(), entries.end());
  return kernels;
}

SampleBatch random_samples(RandomStream& rng, std::int32_t count) {
  SampleBatch batch;
  for (std::int32_t i = 0; i < count; ++i) {
    const auto s = static_cast<std::int32_t>(rng.uniform_index(kStates));
    const auto a = static_cast<std::int32_t>(rng.uniform_index(kActions));
    const auto next = static_cast<std::int32_t>(rng.uniform_index(kStates));
    batch.add(s, a, rng.uniform() - 0.3, next, rng.uniform() < 0.1,
              1.0 + static_cast<double>(rng.uniform_index(5)));
  }
  return batch;
}

// The definitions of lspi.hpp, with dense n x k matrices.
struct DirectSystem {
  Eigen::MatrixXd a;
  Eigen::VectorXd b;
};

DirectSystem direct_system(const SparseRowMatrix& features, const SampleBatch& batch,
                           const std::vector<std::int32_t>& policy, LspiSolver solver,
                           double gamma) {
  const Eigen::MatrixXd table = Eigen::MatrixXd(features);
  const auto n = static_cast<Eigen::Index>(batch.size());
  Eigen::MatrixXd phi(n, features.cols()), phi_next = Eigen::MatrixXd::Zero(n, features.cols());
  Eigen::VectorXd w(n), r(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const auto u = static_cast<std::size_t>(i);
    phi.row(i) = table.row(batch.states[u] * kActions + batch.actions[u]);
    if (!batch.terminals[u]) {
      const std::int32_t next = batch.next_states[u];
      phi_next.row(i) = table.row(next * kActions + policy[static_cast<std::size_t>(next)]);
    }
    w(i) = batch.weights[u];
    r(i) = batch.rewards[u];
  }
  const Eigen::MatrixXd psi = phi - gamma * phi_next;
  if (solver == LspiSolver::brm) {
    return {psi.transpose() * w.asDiagonal() * psi, psi.transpose() * w.asDiagonal() * r};
  }
  return {phi.transpose() * w.asDiagonal() * psi, phi.transpose() * w.asDiagonal() * r};
}

class ActionBlockSystemTest : public testing::TestWithParam<LspiSolver> {};

TEST_P(ActionBlockSystemTest, EqualsTheDefinitionForEveryPolicy) {
  RandomStream rng(31, 0, 0);
  const SparseRowMatrix state_kernels = random_state_kernels(rng);
  const SampleBatch batch = random_samples(rng, 300);
  const EmpiricalTransitionModel model(kStates, kActions, batch.states, batch.actions,
                                       batch.next_states, batch.weights);
  for (const SparseRowMatrix& features :
       {copy_basis(state_kernels, kActions), shift_basis(state_kernels, kActions, model)}) {
    ASSERT_EQ(action_block_violation(features, kActions), "");
    const ActionBlockSystem system(features, kActions, batch, GetParam(), 0.9);
    for (int trial = 0; trial < 4; ++trial) {
      std::vector<std::int32_t> policy(kStates);
      for (std::int32_t& action : policy) {
        action = static_cast<std::int32_t>(rng.uniform_index(kActions));
      }
      Eigen::MatrixXd a;
      Eigen::VectorXd b;
      system.assemble(policy, a, b);
      const DirectSystem expected = direct_system(features, batch, policy, GetParam(), 0.9);
      const double scale = expected.a.cwiseAbs().maxCoeff();
      EXPECT_LT((a - expected.a).cwiseAbs().maxCoeff(), 1e-12 * scale) << "trial " << trial;
      EXPECT_LT((b - expected.b).cwiseAbs().maxCoeff(), 1e-12 * scale) << "trial " << trial;
      // Exact zeros of the definition stay exact zeros (the solver's pattern).
      EXPECT_EQ(((a.array() == 0.0) != (expected.a.array() == 0.0)).count(), 0);
    }
  }
}

// update() against the full rebuild: policies that change a few states at a time
// (rank-r updates), one that changes most (a rebuild, bit for bit as assemble), and
// policies that empty whole (a_i, b_i) groups (their blocks back to exact zeros).
TEST_P(ActionBlockSystemTest, UpdateEqualsTheFullRebuild) {
  RandomStream rng(37, 0, 0);
  const SparseRowMatrix state_kernels = random_state_kernels(rng);
  const SampleBatch batch = random_samples(rng, 300);
  const EmpiricalTransitionModel model(kStates, kActions, batch.states, batch.actions,
                                       batch.next_states, batch.weights);
  for (const SparseRowMatrix& features :
       {copy_basis(state_kernels, kActions), shift_basis(state_kernels, kActions, model)}) {
    ActionBlockSystem system(features, kActions, batch, GetParam(), 0.9);
    std::vector<std::int32_t> policy(kStates, 0);
    Eigen::MatrixXd a, full_a;
    Eigen::VectorXd b, full_b;
    std::int32_t updates = 0, rebuilds = 0;
    for (int trial = 0; trial < 40; ++trial) {
      if (trial == 20) {  // most states change: a rebuild
        for (std::int32_t& action : policy) action = (action + 1) % kActions;
      } else if (trial % 7 == 6) {  // every state to one action: the other groups empty
        policy.assign(kStates, trial % kActions);
      } else {
        for (int change = 0; change < 3; ++change) {
          policy[rng.uniform_index(kStates)] =
              static_cast<std::int32_t>(rng.uniform_index(kActions));
        }
      }
      system.update(policy, a, b);
      system.assemble(policy, full_a, full_b);
      (system.last_update_rebuilt() ? rebuilds : updates) += 1;
      if (system.last_update_rebuilt()) {
        EXPECT_EQ(a, full_a) << "trial " << trial;  // bit for bit
        EXPECT_EQ(b, full_b) << "trial " << trial;
      }
      const double scale = full_a.cwiseAbs().maxCoeff();
      EXPECT_LT((a - full_a).cwiseAbs().maxCoeff(), 1e-13 * scale) << "trial " << trial;
      EXPECT_LT((b - full_b).cwiseAbs().maxCoeff(), 1e-13 * scale) << "trial " << trial;
      const DirectSystem expected = direct_system(features, batch, policy, GetParam(), 0.9);
      EXPECT_LT((a - expected.a).cwiseAbs().maxCoeff(), 1e-12 * scale) << "trial " << trial;
    }
    EXPECT_GT(updates, 20);
    EXPECT_GE(rebuilds, 2);
  }
}

// Readable test names ("brm"), not gtest's byte dumps.
std::string solver_case_name(const testing::TestParamInfo<LspiSolver>& param) {
  return to_string(param.param);
}

INSTANTIATE_TEST_SUITE_P(Solvers, ActionBlockSystemTest,
                         testing::Values(LspiSolver::brm, LspiSolver::lstdq), solver_case_name);

TEST(ActionBlockSystem, NamesTheFirstRowOutsideItsBlock) {
  SparseRowMatrix features(4, 4);  // 2 states x 2 actions, p = 2
  features.insert(0, 0) = 1.0;
  features.insert(1, 3) = 1.0;
  features.insert(3, 1) = 1.0;  // state 1, action 1: belongs in columns [2, 4)
  EXPECT_EQ(action_block_violation(features, 2),
            "row 3 (action 1) has an entry in column 1, outside its block [2, 4)");
  EXPECT_EQ(action_block_violation(SparseRowMatrix(4, 5), 2),
            "the feature table has 5 columns, not a multiple of 2 actions");
}

}  // namespace
}  // namespace ggk::kernels
