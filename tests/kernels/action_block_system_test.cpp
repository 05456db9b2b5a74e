#include "kernels/action_block_system.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include <gtest/gtest.h>

#include "kernels/csr_graph.hpp"
#include "kernels/dense_solvers.hpp"
#include "kernels/gaussian_kernels.hpp"
#include "kernels/lspi.hpp"
#include "kernels/random_stream.hpp"
#include "kernels/shortest_paths.hpp"
#include "kernels/state_action_basis.hpp"
#include "kernels/transition_model.hpp"

namespace ggk::kernels {
namespace {

constexpr std::int32_t kStates = 40;
constexpr std::int32_t kActions = 3;
constexpr std::int32_t kCenters = 7;

// Random state kernels with about a third of the entries zero (as truncated
// kernels), or none (`dense`: as untruncated kernels, every entry non-zero).
SparseRowMatrix random_state_kernels(RandomStream& rng, bool dense = false) {
  SparseRowMatrix kernels(kStates, kCenters);
  std::vector<Eigen::Triplet<double>> entries;
  for (std::int32_t s = 0; s < kStates; ++s) {
    for (std::int32_t j = 0; j < kCenters; ++j) {
      if (!dense && rng.uniform() < 0.35) continue;
      entries.emplace_back(s, j, 0.01 + rng.uniform());
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
// (rank-r updates), one that changes most (a rebuild, bit for bit as assemble, or
// for a copy table, whose later rebuilds subtract, within rounding), and policies
// that empty whole (a_i, b_i) groups (their blocks back to exact zeros). Tables
// with zeros (entry counts kept) and the dense copy table (no zero anywhere: BRM's
// right-hand side counts its non-zero rewards per group instead).
TEST_P(ActionBlockSystemTest, UpdateEqualsTheFullRebuild) {
  RandomStream rng(37, 0, 0);
  const SparseRowMatrix state_kernels = random_state_kernels(rng);
  const SparseRowMatrix dense_kernels = random_state_kernels(rng, true);
  const SampleBatch batch = random_samples(rng, 300);
  const EmpiricalTransitionModel model(kStates, kActions, batch.states, batch.actions,
                                       batch.next_states, batch.weights);
  for (const SparseRowMatrix& features :
       {copy_basis(state_kernels, kActions), shift_basis(state_kernels, kActions, model),
        copy_basis(dense_kernels, kActions)}) {
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
      if (system.last_update_rebuilt() && !system.last_update_subtracted()) {
        EXPECT_EQ(a, full_a) << "trial " << trial;  // bit for bit
      }
      if (system.last_update_rebuilt()) {
        EXPECT_EQ(b, full_b) << "trial " << trial;
      }
      const double scale = full_a.cwiseAbs().maxCoeff();
      EXPECT_LT((a - full_a).cwiseAbs().maxCoeff(), 1e-13 * scale) << "trial " << trial;
      EXPECT_LT((b - full_b).cwiseAbs().maxCoeff(), 1e-13 * scale) << "trial " << trial;
      const DirectSystem expected = direct_system(features, batch, policy, GetParam(), 0.9);
      EXPECT_LT((a - expected.a).cwiseAbs().maxCoeff(), 1e-12 * scale) << "trial " << trial;
      // Exact zeros of the rebuild stay exact zeros, never rounding residue.
      EXPECT_EQ(((a.array() == 0.0) != (full_a.array() == 0.0)).count(), 0) << "trial " << trial;
      EXPECT_EQ(((b.array() == 0.0) != (full_b.array() == 0.0)).count(), 0) << "trial " << trial;
    }
    EXPECT_GT(updates, 20);
    EXPECT_GE(rebuilds, 2);
  }
}

// The copy basis from its state kernels: a rebuild after the first forms the
// largest group's blocks by subtraction from the sums over the bootstrap actions.
// Against the directly summed system (assemble): b bit for bit (summed directly),
// A within a few ulps of the totals' magnitude (the bound: 4 m eps times the
// largest |entry| of gamma sum_y C_xy and gamma^2 sum_y E_y, which is at most
// A's largest entry times (1 + gamma)^2 here), exact zeros where the direct sum
// has them (no sample of the group reaches: reset by the counts), BRM and LSTD-Q,
// kernels with zeros (random, banded) and without. The first rebuild is the direct one, bit for
// bit, and only rebuilds subtract (a rank-r update does not).
TEST_P(ActionBlockSystemTest, RebuildsBySubtractionStayWithinRoundingOfTheTotals) {
  RandomStream rng(41, 0, 0);
  const SampleBatch batch = random_samples(rng, 400);
  // Banded kernels (each centre reaches 7 of the 40 states, as truncated ones do):
  // entries of a group's block that none of its samples reaches.
  std::vector<Eigen::Triplet<double>> band;
  for (std::int32_t s = 0; s < kStates; ++s) {
    for (std::int32_t j = 0; j < kCenters; ++j) {
      if (std::abs(s - 6 * j - 3) < 4) band.emplace_back(s, j, 0.5 + rng.uniform());
    }
  }
  SparseRowMatrix banded(kStates, kCenters);
  banded.setFromTriplets(band.begin(), band.end());
  for (const SparseRowMatrix& kernels :
       {random_state_kernels(rng), banded, random_state_kernels(rng, true)}) {
    ActionBlockSystem system(ActionBlockSystem::copy_basis_tag, kernels, kActions, batch,
                             GetParam(), 0.9);
    std::vector<std::int32_t> policy(kStates, 0);
    Eigen::MatrixXd a, full_a;
    Eigen::VectorXd b, full_b;
    std::int32_t subtracted = 0;
    for (int trial = 0; trial < 24; ++trial) {
      if (trial % 3 == 2) {  // a few states: a rank-r update
        policy[rng.uniform_index(kStates)] = static_cast<std::int32_t>(rng.uniform_index(kActions));
      } else {  // most states, mostly to one action (as the Khepera's "forward"): a rebuild
        for (std::int32_t& action : policy) {
          action = rng.uniform() < 0.7 ? trial % kActions
                                       : static_cast<std::int32_t>(rng.uniform_index(kActions));
        }
      }
      system.update(policy, a, b);
      system.assemble(policy, full_a, full_b);
      EXPECT_EQ(system.last_update_subtracted(), system.last_update_rebuilt() && trial > 0)
          << "trial " << trial;
      if (trial == 0) {
        EXPECT_EQ(a, full_a);
      }
      subtracted += system.last_update_subtracted() ? 1 : 0;
      if (!system.last_update_subtracted()) continue;
      EXPECT_EQ(b, full_b) << "trial " << trial;
      const double bound = 4.0 * kActions * std::numeric_limits<double>::epsilon() * 1.9 * 1.9 *
                           full_a.cwiseAbs().maxCoeff();
      EXPECT_LE((a - full_a).cwiseAbs().maxCoeff(), bound) << "trial " << trial;
      EXPECT_GT((a - full_a).cwiseAbs().maxCoeff(), 0.0) << "trial " << trial;  // not the sums
      EXPECT_EQ(((a.array() == 0.0) != (full_a.array() == 0.0)).count(), 0) << "trial " << trial;
    }
    EXPECT_GE(subtracted, 10);
  }
}

// A truncated-kernel problem as jobs/ci.toml makes it with basis.truncation =
// 0.05 and sigma = 2 (issue 23): the four-rooms map of jobs/maps, 4 moves (a move
// into a wall stays), reward 1 on entering a goal 'G' (terminal; the walk goes on
// from a random start), 20 random walks of 500 moves, GGK of 16 centres on the
// sample graph (the goals first, then random visited cells; truncated at 0.05,
// each kernel reaches about 5 cells), shift basis. Where no reward reaches the
// system Q is exactly 0 and the greedy step's ties go to action 0.
struct TruncatedMaze {
  SampleBatch samples;
  SparseRowMatrix features;
  std::int32_t num_states = 0;
};

TruncatedMaze truncated_maze(std::uint64_t seed) {
  const std::vector<std::string> rows = {
      "#######################", "#..........#GG........#", "#..........#GG........#",
      "#..........#..........#", "#..........#..........#", "#..........#..........#",
      "#..........#..........#", "#..........#..........#", "#.....................#",
      "#..........#..........#", "#..........#..........#", "####.############.#####",
      "#..........#..........#", "#..........#..........#", "#..........#..........#",
      "#.....................#", "#..........#..........#", "#..........#..........#",
      "#..........#..........#", "#..........#..........#", "#..........#..........#",
      "#..........#..........#", "#######################"};
  const auto side = static_cast<std::int32_t>(rows.size());
  const auto cell = [&](std::int32_t r, std::int32_t c) {
    return rows[static_cast<std::size_t>(r)][static_cast<std::size_t>(c)];
  };
  constexpr std::int32_t kMoves = 4;
  TruncatedMaze maze;
  maze.num_states = side * side;
  std::vector<std::int32_t> starts, goals;
  for (std::int32_t s = 0; s < maze.num_states; ++s) {
    if (cell(s / side, s % side) == '.') starts.push_back(s);
    if (cell(s / side, s % side) == 'G') goals.push_back(s);
  }
  RandomStream rng(seed, 0, 0);
  SampleBatch walk;
  for (int series = 0; series < 20; ++series) {
    std::int32_t s = starts[rng.uniform_index(starts.size())];
    for (int step = 0; step < 500; ++step) {
      const auto a = static_cast<std::int32_t>(rng.uniform_index(kMoves));
      const std::int32_t r = s / side + (a == 0 ? -1 : a == 1 ? 1 : 0);
      const std::int32_t c = s % side + (a == 2 ? -1 : a == 3 ? 1 : 0);
      const std::int32_t next = cell(r, c) == '#' ? s : r * side + c;
      const bool goal = cell(r, c) == 'G';
      walk.add(s, a, goal ? 1.0 : 0.0, next, goal);
      s = goal ? starts[rng.uniform_index(starts.size())] : next;
    }
  }
  maze.samples = fold_duplicate_samples(walk);
  RowMatrixXd cells(maze.num_states, 2);
  for (std::int32_t s = 0; s < maze.num_states; ++s) {
    cells(s, 0) = s / side;
    cells(s, 1) = s % side;
  }
  std::vector<NodeTransition> moves;
  std::vector<std::int32_t> visited;
  for (std::size_t i = 0; i < maze.samples.size(); ++i) {
    moves.push_back({maze.samples.states[i], maze.samples.next_states[i]});
    visited.push_back(maze.samples.states[i]);
  }
  std::sort(visited.begin(), visited.end());
  visited.erase(std::unique(visited.begin(), visited.end()), visited.end());
  shuffle(visited, rng);
  std::vector<std::int32_t> centers = goals;
  for (std::size_t i = 0; centers.size() < 16; ++i) centers.push_back(visited[i]);
  const RowMatrixXd distances = geodesic_distances(transition_graph(cells, moves), centers);
  const SparseRowMatrix kernels = geodesic_gaussian_kernels(distances, 2.0, 0.05);
  const EmpiricalTransitionModel model(maze.num_states, kMoves, maze.samples.states,
                                       maze.samples.actions, maze.samples.next_states,
                                       maze.samples.weights);
  maze.features = shift_basis(kernels, kMoves, model);
  return maze;
}

// Policy iteration on the truncated maze, every evaluation twice: the system from
// update() (a rank-r update wherever fewer than half the samples changed
// bootstrap action) and the one assemble() builds afresh. They must have the
// same exact zeros (A, b and the weights) and agree elsewhere to rounding, so the
// greedy policy is the same at every iteration. Rounding residue left where a
// removal emptied an entry would break Q's exact ties at 0 (issue 23).
TEST_P(ActionBlockSystemTest, UpdatesKeepTheExactZerosOfTruncatedKernels) {
  const TruncatedMaze maze = truncated_maze(1);
  constexpr std::int32_t kMoves = 4;
  const double ridge = 1e-6;
  ActionBlockSystem system(maze.features, kMoves, maze.samples, GetParam(), 0.9);
  DenseSymmetricSolver cholesky;
  DenseLuSolver lu;
  const auto solve = [&](const Eigen::MatrixXd& a, const Eigen::VectorXd& b) {
    Eigen::VectorXd w;
    const SolveReport report = GetParam() == LspiSolver::brm
                                   ? cholesky.solve(a, ridge, b, w)
                                   : lu.solve(a, ridge, b, w, system.block_size());
    EXPECT_TRUE(report.ok) << report.message;
    return w;
  };
  std::vector<std::int32_t> policy(static_cast<std::size_t>(maze.num_states), 0);
  Eigen::MatrixXd a, full_a;
  Eigen::VectorXd b, full_b;
  std::int32_t updates = 0, zero_weights = 0;
  for (int iteration = 1; iteration <= 20; ++iteration) {
    system.update(policy, a, b);
    system.assemble(policy, full_a, full_b);
    updates += system.last_update_rebuilt() ? 0 : 1;
    const double scale = full_a.cwiseAbs().maxCoeff();
    EXPECT_EQ(((a.array() == 0.0) != (full_a.array() == 0.0)).count(), 0)
        << "iteration " << iteration;
    EXPECT_EQ(((b.array() == 0.0) != (full_b.array() == 0.0)).count(), 0)
        << "iteration " << iteration;
    EXPECT_LT((a - full_a).cwiseAbs().maxCoeff(), 1e-13 * scale) << "iteration " << iteration;
    EXPECT_LT((b - full_b).cwiseAbs().maxCoeff(), 1e-13 * scale) << "iteration " << iteration;
    const Eigen::VectorXd w = solve(a, b), full_w = solve(full_a, full_b);
    EXPECT_EQ(((w.array() == 0.0) != (full_w.array() == 0.0)).count(), 0)
        << "iteration " << iteration;
    zero_weights += static_cast<std::int32_t>((full_w.array() == 0.0).count());
    const std::vector<std::int32_t> improved = greedy_policy(maze.features, kMoves, w);
    ASSERT_EQ(improved, greedy_policy(maze.features, kMoves, full_w)) << "iteration " << iteration;
    if (improved == policy) break;
    policy = improved;
  }
  EXPECT_GE(updates, 2);       // the rank-r path ran
  EXPECT_GT(zero_weights, 0);  // and the exact zeros it must keep are there
}

// Readable test names ("brm"), not gtest's byte dumps.
std::string solver_param_name(const testing::TestParamInfo<LspiSolver>& param) {
  return to_string(param.param);
}

INSTANTIATE_TEST_SUITE_P(Solvers, ActionBlockSystemTest,
                         testing::Values(LspiSolver::brm, LspiSolver::lstdq), solver_param_name);

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
