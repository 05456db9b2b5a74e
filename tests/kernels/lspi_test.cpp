#include "kernels/lspi.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "kernels/action_block_system.hpp"
#include "kernels/gaussian_kernels.hpp"
#include "kernels/random_stream.hpp"
#include "kernels/state_action_basis.hpp"

namespace ggk::kernels {
namespace {

// A finite MDP in tabular form, for exact policy iteration.
struct TabularMdp {
  int num_states = 0, num_actions = 0;
  // Per (s, a) = s * m + a: successors, probabilities, reward, and which successors end the
  // episode.
  std::vector<std::vector<int>> next;
  std::vector<std::vector<double>> prob;
  std::vector<double> reward;
  int terminal_state = -1;  // entering it ends the episode
};

TabularMdp random_mdp(int n, int m, bool deterministic, bool with_terminal, std::uint64_t seed) {
  RandomStream rng(seed, 0, 0);
  TabularMdp mdp;
  mdp.num_states = n;
  mdp.num_actions = m;
  mdp.terminal_state = with_terminal ? n - 1 : -1;
  for (int sa = 0; sa < n * m; ++sa) {
    const int successors = deterministic ? 1 : 1 + static_cast<int>(rng.uniform_index(3));
    std::vector<int> next;
    std::vector<double> prob;
    double total = 0;
    for (int k = 0; k < successors; ++k) {
      int s_next = static_cast<int>(rng.uniform_index(n));
      if (std::find(next.begin(), next.end(), s_next) != next.end()) continue;
      next.push_back(s_next);
      prob.push_back(rng.uniform(0.1, 1.0));
      total += prob.back();
    }
    for (double& p : prob) p /= total;
    mdp.next.push_back(next);
    mdp.prob.push_back(prob);
    mdp.reward.push_back(rng.uniform(-1.0, 1.0));
  }
  return mdp;
}

// Exact policy iteration from the all-zeros policy, same tie rule as LSPI.
struct ExactSolution {
  std::vector<std::int32_t> policy;
  Eigen::VectorXd q;
  int iterations = 0;
};

ExactSolution exact_policy_iteration(const TabularMdp& mdp, double gamma) {
  const int n = mdp.num_states, m = mdp.num_actions;
  ExactSolution sol;
  sol.policy.assign(n, 0);
  for (int iteration = 1; iteration <= 100; ++iteration) {
    Eigen::MatrixXd a = Eigen::MatrixXd::Identity(n * m, n * m);
    Eigen::VectorXd r(n * m);
    for (int sa = 0; sa < n * m; ++sa) {
      r(sa) = mdp.reward[sa];
      for (std::size_t k = 0; k < mdp.next[sa].size(); ++k) {
        const int s_next = mdp.next[sa][k];
        if (s_next == mdp.terminal_state) continue;
        a(sa, s_next * m + sol.policy[s_next]) -= gamma * mdp.prob[sa][k];
      }
    }
    sol.q = a.partialPivLu().solve(r);
    sol.iterations = iteration;
    int changes = 0;
    for (int s = 0; s < n; ++s) {
      int best = 0;
      for (int act = 1; act < m; ++act)
        if (sol.q(s * m + act) > sol.q(s * m + best)) best = act;
      changes += best != sol.policy[s];
      sol.policy[s] = best;
    }
    if (changes == 0) break;
  }
  return sol;
}

// One weighted sample per (s, a, s') with weight P(s'|s,a): the batch holds the model exactly.
SampleBatch full_coverage_samples(const TabularMdp& mdp) {
  SampleBatch batch;
  for (int s = 0; s < mdp.num_states; ++s)
    for (int a = 0; a < mdp.num_actions; ++a) {
      const int sa = s * mdp.num_actions + a;
      for (std::size_t k = 0; k < mdp.next[sa].size(); ++k) {
        const int s_next = mdp.next[sa][k];
        batch.add(s, a, mdp.reward[sa], s_next, s_next == mdp.terminal_state, mdp.prob[sa][k]);
      }
    }
  return batch;
}

// One indicator per (s, a): column a * n + s (copy scheme of the identity kernel).
SparseRowMatrix tabular_features(int n, int m) {
  SparseRowMatrix identity(n, n);
  identity.setIdentity();
  return copy_basis(identity, m);
}

struct TabularCase {
  LspiSolver solver;
  bool deterministic;
  bool with_terminal;
};

class TabularLspiEqualsPolicyIteration : public testing::TestWithParam<TabularCase> {};

// BRM's fixed point equals the Bellman solution only for deterministic transitions
// (double-sampling bias otherwise), so BRM is checked on deterministic MDPs and
// LSTD-Q on stochastic and deterministic ones.
TEST_P(TabularLspiEqualsPolicyIteration, PolicyAndQMatch) {
  const TabularCase param = GetParam();
  for (std::uint64_t seed = 1; seed <= 10; ++seed) {
    const TabularMdp mdp = random_mdp(20, 4, param.deterministic, param.with_terminal, seed);
    const ExactSolution exact = exact_policy_iteration(mdp, 0.9);
    LspiOptions options;
    options.solver = param.solver;
    options.max_iterations = 100;
    const SparseRowMatrix features = tabular_features(20, 4);
    const LspiResult result = fit_lspi(features, 4, full_coverage_samples(mdp), options);
    ASSERT_EQ(result.status, LspiStatus::converged) << result.message;
    EXPECT_EQ(result.policy, exact.policy) << "seed " << seed;
    EXPECT_EQ(result.iterations(), exact.iterations) << "seed " << seed;
    EXPECT_LT((action_values(features, result.weights) - exact.q).lpNorm<Eigen::Infinity>(), 1e-8)
        << "seed " << seed;
    EXPECT_EQ(result.history.back().policy_changes, 0);
  }
}

// Readable test names ("lstdq_stochastic_terminal"), not gtest's byte dumps.
std::string tabular_case_name(const testing::TestParamInfo<TabularCase>& param) {
  return std::string(to_string(param.param.solver)) +
         (param.param.deterministic ? "_deterministic" : "_stochastic") +
         (param.param.with_terminal ? "_terminal" : "_no_terminal");
}

std::string solver_case_name(const testing::TestParamInfo<LspiSolver>& param) {
  return to_string(param.param);
}

INSTANTIATE_TEST_SUITE_P(Solvers, TabularLspiEqualsPolicyIteration,
                         testing::Values(TabularCase{LspiSolver::lstdq, false, false},
                                         TabularCase{LspiSolver::lstdq, false, true},
                                         TabularCase{LspiSolver::lstdq, true, true},
                                         TabularCase{LspiSolver::brm, true, false},
                                         TabularCase{LspiSolver::brm, true, true}),
                         tabular_case_name);

// Kernel features on a chain: 30 states on a line, 5 centres.
SparseRowMatrix chain_features(int n, int m) {
  RowMatrixXd states(n, 1), centers(5, 1);
  for (int s = 0; s < n; ++s) states(s, 0) = s;
  for (int j = 0; j < 5; ++j) centers(j, 0) = j * (n - 1) / 4.0;
  return copy_basis(ordinary_gaussian_kernels(states, centers, 4.0), m);
}

SampleBatch random_chain_walk(int n, int steps, std::uint64_t seed) {
  RandomStream rng(seed, 0, 0);
  SampleBatch batch;
  int s = static_cast<int>(rng.uniform_index(n));
  for (int t = 0; t < steps; ++t) {
    const int a = static_cast<int>(rng.uniform_index(2));
    const int s_next = std::clamp(s + (a == 0 ? -1 : 1), 0, n - 1);
    const bool goal = s_next == n - 1;
    batch.add(s, a, goal ? 1.0 : 0.0, s_next, goal);
    s = goal ? static_cast<int>(rng.uniform_index(n)) : s_next;
  }
  return batch;
}

class FoldedSamples : public testing::TestWithParam<LspiSolver> {};

TEST_P(FoldedSamples, GiveTheSameWeightsAsTheUnfoldedBatch) {
  const SparseRowMatrix features = chain_features(30, 2);
  const SampleBatch batch = random_chain_walk(30, 3000, 5);
  const SampleBatch folded = fold_duplicate_samples(batch);
  ASSERT_LT(folded.size(), batch.size() / 10);  // the walk revisits transitions a lot
  LspiOptions options;
  options.solver = GetParam();
  options.ridge = 1e-6;
  const LspiResult full = fit_lspi(features, 2, batch, options);
  const LspiResult compact = fit_lspi(features, 2, folded, options);
  ASSERT_TRUE(full.ok()) << full.message;
  ASSERT_TRUE(compact.ok()) << compact.message;
  EXPECT_EQ(full.iterations(), compact.iterations());
  EXPECT_EQ(full.policy, compact.policy);
  EXPECT_LT((full.weights - compact.weights).norm(), 1e-9 * full.weights.norm());
  // The learned policy walks right, towards the goal. (Five wide kernels cannot
  // resolve the tiny values near the far wall, where LSTD-Q picks left at s <= 3.)
  for (int s = 8; s < 29; ++s) EXPECT_EQ(full.policy[s], 1) << "state " << s;
}

INSTANTIATE_TEST_SUITE_P(Solvers, FoldedSamples,
                         testing::Values(LspiSolver::brm, LspiSolver::lstdq), solver_case_name);

class RankDeficient : public testing::TestWithParam<LspiSolver> {};

TEST_P(RankDeficient, IsReportedWithoutRidgeAndRegularisedWithIt) {
  // 12 basis functions, samples on only 3 distinct (s, a) pairs.
  const SparseRowMatrix features = tabular_features(6, 2);
  SampleBatch batch;
  batch.add(0, 0, 1.0, 1, false);
  batch.add(1, 1, 0.0, 2, false);
  batch.add(2, 0, 0.5, 0, false);
  LspiOptions options;
  options.solver = GetParam();
  const LspiResult singular = fit_lspi(features, 2, batch, options);
  EXPECT_EQ(singular.status, LspiStatus::solver_failed);
  EXPECT_FALSE(singular.message.empty());
  EXPECT_EQ(singular.weights.size(), 0);

  options.ridge = 1e-3;
  const LspiResult regularised = fit_lspi(features, 2, batch, options);
  ASSERT_TRUE(regularised.ok()) << regularised.message;
  EXPECT_TRUE(regularised.weights.allFinite());
  EXPECT_EQ(regularised.weights.size(), 12);
}

INSTANTIATE_TEST_SUITE_P(Solvers, RankDeficient,
                         testing::Values(LspiSolver::brm, LspiSolver::lstdq), solver_case_name);

TEST(Lspi, BrmReusesTheSymbolicAnalysisWhenThePatternHolds) {
  const SparseRowMatrix features = chain_features(30, 2);
  LspiOptions options;
  options.ridge = 1e-6;
  options.linear_algebra = LinearAlgebra::sparse;
  const LspiResult result = fit_lspi(features, 2, random_chain_walk(30, 2000, 9), options);
  ASSERT_GE(result.iterations(), 2);
  EXPECT_FALSE(result.history[0].reused_analysis);
  // Dense Gaussian features: every iteration's matrix has the same full pattern.
  EXPECT_TRUE(result.history[1].reused_analysis);
}

// The dense kind (LAPACK) meets the exact answers as the sparse one does: both
// solvers, stochastic and deterministic, with and without terminal states.
TEST(Lspi, DenseLinearAlgebraEqualsPolicyIterationOnTabularMdps) {
  for (const LspiSolver solver : {LspiSolver::brm, LspiSolver::lstdq}) {
    for (std::uint64_t seed = 1; seed <= 5; ++seed) {
      const bool deterministic = solver == LspiSolver::brm || seed % 2 == 0;
      const TabularMdp mdp = random_mdp(20, 4, deterministic, seed % 3 != 0, seed);
      const ExactSolution exact = exact_policy_iteration(mdp, 0.9);
      LspiOptions options;
      options.solver = solver;
      options.max_iterations = 100;
      options.linear_algebra = LinearAlgebra::dense;
      const SparseRowMatrix features = tabular_features(20, 4);
      const LspiResult result = fit_lspi(features, 4, full_coverage_samples(mdp), options);
      ASSERT_EQ(result.status, LspiStatus::converged) << result.message;
      EXPECT_EQ(result.policy, exact.policy) << to_string(solver) << " seed " << seed;
      EXPECT_LT((action_values(features, result.weights) - exact.q).lpNorm<Eigen::Infinity>(), 1e-8)
          << to_string(solver) << " seed " << seed;
      for (const LspiIteration& iteration : result.history) EXPECT_TRUE(iteration.dense_solve);
    }
  }
}

// Dense and sparse factorisations of the same systems: the same policies, hence
// the same assembled systems bit for bit (A does not depend on the solver), and
// weights equal to rounding.
TEST(Lspi, DenseAndSparseLinearAlgebraAgreeToRounding) {
  const SparseRowMatrix features = chain_features(30, 2);
  const SampleBatch samples = random_chain_walk(30, 2000, 9);
  for (const LspiSolver solver : {LspiSolver::brm, LspiSolver::lstdq}) {
    LspiOptions options;
    options.solver = solver;
    options.ridge = 1e-6;
    options.linear_algebra = LinearAlgebra::sparse;
    const LspiResult sparse = fit_lspi(features, 2, samples, options);
    options.linear_algebra = LinearAlgebra::dense;
    const LspiResult dense = fit_lspi(features, 2, samples, options);
    ASSERT_TRUE(sparse.ok() && dense.ok()) << sparse.message << dense.message;
    ASSERT_EQ(sparse.iterations(), dense.iterations());
    EXPECT_EQ(sparse.policy, dense.policy);
    EXPECT_TRUE(sparse.a.isApprox(dense.a, 0.0)) << "A must be the same bits";
    EXPECT_EQ(sparse.a.nonZeros(), dense.a.nonZeros());
    EXPECT_EQ(sparse.b, dense.b);
    EXPECT_LT((sparse.weights - dense.weights).norm(), 1e-9 * sparse.weights.norm());
    for (std::int32_t i = 0; i < sparse.iterations(); ++i) {
      EXPECT_FALSE(sparse.history[static_cast<std::size_t>(i)].dense_solve);
      EXPECT_TRUE(dense.history[static_cast<std::size_t>(i)].dense_solve);
      EXPECT_FALSE(dense.history[static_cast<std::size_t>(i)].reused_analysis);
    }
  }
}

// RidgeScale::relative adds lambda times the mean absolute diagonal entry of the
// evaluation's system: one evaluation with it equals one with that absolute ridge,
// for both solvers and both kinds of linear algebra.
TEST(Lspi, RelativeRidgeIsLambdaTimesTheMeanAbsoluteDiagonal) {
  const SparseRowMatrix features = chain_features(30, 2);
  const SampleBatch samples = random_chain_walk(30, 2000, 9);
  for (const LspiSolver solver : {LspiSolver::brm, LspiSolver::lstdq}) {
    for (const LinearAlgebra kind : {LinearAlgebra::sparse, LinearAlgebra::dense}) {
      LspiOptions options;
      options.solver = solver;
      options.linear_algebra = kind;
      options.max_iterations = 1;
      options.ridge = 1e-9;  // A + 1e-9 I: the system's scale, read back
      const LspiResult probe = fit_lspi(features, 2, samples, options);
      ASSERT_TRUE(probe.ok()) << probe.message;
      const Eigen::VectorXd diagonal = Eigen::MatrixXd(probe.a).diagonal().array() - 1e-9;
      const double scale = diagonal.cwiseAbs().sum() / static_cast<double>(diagonal.size());
      ASSERT_GT(scale, 1.0);  // so that lambda and lambda * scale differ

      options.ridge = 1e-3;
      options.ridge_scale = RidgeScale::relative;
      const LspiResult relative = fit_lspi(features, 2, samples, options);
      options.ridge = 1e-3 * scale;
      options.ridge_scale = RidgeScale::absolute;
      const LspiResult absolute = fit_lspi(features, 2, samples, options);
      ASSERT_TRUE(relative.ok() && absolute.ok()) << relative.message << absolute.message;
      EXPECT_LT((relative.weights - absolute.weights).norm(), 1e-9 * absolute.weights.norm())
          << to_string(solver) << ", " << to_string(kind);
      EXPECT_TRUE(relative.a.isApprox(absolute.a, 1e-12)) << to_string(solver);
      options.ridge = 1e-3;
      const LspiResult plain = fit_lspi(features, 2, samples, options);
      EXPECT_GT((plain.weights - relative.weights).norm(), 1e-6 * plain.weights.norm())
          << "the relative ridge made no difference: " << to_string(solver);
    }
  }
}

// automatic: dense Gaussian kernels give dense systems (LAPACK), BRM and LSTD-Q;
// one indicator per state-action pair gives a sparse one (CHOLMOD).
TEST(Lspi, AutomaticLinearAlgebraFollowsTheSystemsDensity) {
  LspiOptions options;
  options.ridge = 1e-6;
  ASSERT_EQ(options.linear_algebra, LinearAlgebra::automatic);
  const LspiResult gaussian =
      fit_lspi(chain_features(30, 2), 2, random_chain_walk(30, 2000, 9), options);
  ASSERT_TRUE(gaussian.ok()) << gaussian.message;
  for (const LspiIteration& iteration : gaussian.history) EXPECT_TRUE(iteration.dense_solve);
  const TabularMdp mdp = random_mdp(20, 4, true, false, 3);
  const LspiResult tabular =
      fit_lspi(tabular_features(20, 4), 4, full_coverage_samples(mdp), options);
  ASSERT_TRUE(tabular.ok()) << tabular.message;
  for (const LspiIteration& iteration : tabular.history) EXPECT_FALSE(iteration.dense_solve);
  options.solver = LspiSolver::lstdq;
  const LspiResult lstdq =
      fit_lspi(chain_features(30, 2), 2, random_chain_walk(30, 2000, 9), options);
  ASSERT_TRUE(lstdq.ok()) << lstdq.message;
  for (const LspiIteration& iteration : lstdq.history) EXPECT_TRUE(iteration.dense_solve);
}

// Three actions on the chain (left, right, stay); only "stay" at the last state
// is rewarded (terminal). The first LSTD-Q evaluation (policy: action 0) is block
// lower triangular with b zero in the blocks of actions 0 and 1, so their weights
// are zero in exact arithmetic and Q(s, 0) = Q(s, 1) = 0 ties everywhere: the
// greedy step must see exact zeros (ties to the lowest action), not rounding
// residue. UMFPACK keeps them exact, and so does the dense LU in block triangular
// form; a plain pivoted LU of the whole matrix does not.
TEST(Lspi, LstdqKeepsWeightsThatAreZeroInExactArithmeticExact) {
  const int n = 30;
  RandomStream rng(21, 0, 0);
  SampleBatch batch;
  for (int t = 0; t < 3000; ++t) {
    const int s = static_cast<int>(rng.uniform_index(n));
    const int a = static_cast<int>(rng.uniform_index(3));
    const int s_next = std::clamp(s + (a == 0 ? -1 : a == 1 ? 1 : 0), 0, n - 1);
    const bool goal = a == 2 && s == n - 1;
    batch.add(s, a, goal ? 1.0 : 0.0, s_next, goal);
  }
  for (const LinearAlgebra kind : {LinearAlgebra::sparse, LinearAlgebra::dense}) {
    LspiOptions options;
    options.solver = LspiSolver::lstdq;
    options.ridge = 1e-6;
    options.max_iterations = 1;
    options.linear_algebra = kind;
    const LspiResult result = fit_lspi(chain_features(n, 3), 3, batch, options);
    ASSERT_TRUE(result.ok()) << result.message;
    const Eigen::Index p = result.weights.size() / 3;
    EXPECT_TRUE((result.weights.head(2 * p).array() == 0.0).all())
        << to_string(kind) << ": " << result.weights.head(2 * p).transpose();
    EXPECT_GT(result.weights.tail(p).norm(), 0.0);
  }
}

TEST(Lspi, StopsAtTheIterationCap) {
  const TabularMdp mdp = random_mdp(20, 4, true, false, 3);
  ASSERT_GT(exact_policy_iteration(mdp, 0.9).iterations, 1);
  LspiOptions options;
  options.max_iterations = 1;
  const LspiResult result =
      fit_lspi(tabular_features(20, 4), 4, full_coverage_samples(mdp), options);
  EXPECT_EQ(result.status, LspiStatus::max_iterations);
  EXPECT_EQ(result.iterations(), 1);
}

TEST(Lspi, RejectsInconsistentInputs) {
  const SparseRowMatrix features = tabular_features(3, 2);
  SampleBatch batch;
  batch.add(0, 0, 0.0, 3, false);  // state 3 does not exist
  EXPECT_THROW(fit_lspi(features, 2, batch, {}), std::invalid_argument);
  EXPECT_THROW(fit_lspi(features, 4, SampleBatch{}, {}), std::invalid_argument);
  SparseRowMatrix interleaved(6, 6);  // phi(s, a) in column s * 2 + a: not action blocks
  interleaved.setIdentity();
  EXPECT_THROW(fit_lspi(interleaved, 2, SampleBatch{}, {}), std::invalid_argument);
  LspiOptions bad_gamma;
  bad_gamma.gamma = 1.0;
  EXPECT_THROW(fit_lspi(features, 2, SampleBatch{}, bad_gamma), std::invalid_argument);
}

TEST(Lspi, StateValuesAndGreedyPolicyFollowQ) {
  const SparseRowMatrix features = tabular_features(2, 3);
  Eigen::VectorXd w(6);
  w << 0.1, -1.0, 0.5, -2.0, 0.5, -0.5;  // column a * 2 + s
  EXPECT_EQ(greedy_policy(features, 3, w),
            (std::vector<std::int32_t>{1, 2}));  // ties to the lowest
  const Eigen::VectorXd v = state_values(features, 3, w);
  EXPECT_DOUBLE_EQ(v(0), 0.5);
  EXPECT_DOUBLE_EQ(v(1), -0.5);
}

// fit_lspi_copy_basis from the state kernels alone equals fit_lspi on the copy
// table bit for bit (weights, policy, A, b, history), BRM and LSTD-Q, with
// truncated (sparse) kernels and enough iterations for rank-r updates.
TEST(Lspi, CopyBasisFromStateKernelsEqualsTheTable) {
  constexpr int kStates = 60;
  RandomStream rng(43, 0, 0);
  std::vector<Eigen::Triplet<double>> entries;
  for (int s = 0; s < kStates; ++s) {
    for (int j = 0; j < 8; ++j) {
      const double d = std::abs(s - 8.0 * j);
      if (d < 20.0) entries.emplace_back(s, j, std::exp(-d * d / 50.0));
    }
  }
  SparseRowMatrix state_kernels(kStates, 8);
  state_kernels.setFromTriplets(entries.begin(), entries.end());
  const SampleBatch samples = random_chain_walk(kStates, 3000, 17);
  for (const LspiSolver solver : {LspiSolver::brm, LspiSolver::lstdq}) {
    LspiOptions options;
    options.solver = solver;
    options.ridge = 1e-6;
    const LspiResult table = fit_lspi(copy_basis(state_kernels, 2), 2, samples, options);
    const LspiResult kernels = fit_lspi_copy_basis(state_kernels, 2, samples, options);
    ASSERT_TRUE(table.ok());
    // An uncompressed table is the same table (its rebuilds subtract as well).
    SparseRowMatrix uncompressed = copy_basis(state_kernels, 2);
    uncompressed.uncompress();
    EXPECT_EQ(fit_lspi(uncompressed, 2, samples, options).weights, table.weights);
    EXPECT_EQ(kernels.status, table.status);
    EXPECT_EQ(kernels.weights, table.weights);
    EXPECT_EQ(kernels.policy, table.policy);
    EXPECT_EQ(kernels.b, table.b);
    EXPECT_TRUE(kernels.a.isApprox(table.a, 0.0));
    EXPECT_EQ(Eigen::MatrixXd(kernels.a), Eigen::MatrixXd(table.a));
    ASSERT_EQ(kernels.iterations(), table.iterations());
    for (int i = 0; i < table.iterations(); ++i) {
      EXPECT_EQ(kernels.history[i].policy_changes, table.history[i].policy_changes);
      EXPECT_EQ(kernels.history[i].rcond, table.history[i].rcond);
    }
  }
  SampleBatch outside;
  outside.add(kStates, 0, 0.0, 1, false);  // a state past the kernels' rows
  EXPECT_THROW(fit_lspi_copy_basis(state_kernels, 2, outside, {}), std::invalid_argument);
}

// Fits that differ only in their solver or gamma can share their system's fixed
// part (D_a, the start right-hand side: ActionBlockSystem::copy_basis_fixed, as the
// Khepera's BRM and LSTD-Q fits of one table do): the same fits bit for bit as
// when each forms its own. A part made for other kernels, samples or actions is
// refused, as are uncompressed kernels and samples outside the table.
TEST(Lspi, CopyBasisFitsThatShareTheirFixedPartAreTheSameFits) {
  constexpr int kStates = 24;
  std::vector<Eigen::Triplet<double>> entries;
  for (int s = 0; s < kStates; ++s) {
    for (int j = 0; j < 8; ++j) {
      const double d = std::abs(s - 3.0 * j);
      if (d < 8.0) entries.emplace_back(s, j, std::exp(-d * d / 8.0));
    }
  }
  SparseRowMatrix state_kernels(kStates, 8);
  state_kernels.setFromTriplets(entries.begin(), entries.end());
  const SampleBatch samples = random_chain_walk(kStates, 3000, 19);
  const auto shared = ActionBlockSystem::copy_basis_fixed(state_kernels, 2, samples);
  for (const LspiSolver solver : {LspiSolver::brm, LspiSolver::lstdq}) {
    for (const double gamma : {0.9, 0.5}) {
      LspiOptions options;
      options.solver = solver;
      options.gamma = gamma;
      options.ridge = 1e-6;
      const LspiResult own = fit_lspi_copy_basis(state_kernels, 2, samples, options);
      const LspiResult with_shared =
          fit_lspi_copy_basis(state_kernels, 2, samples, options, shared);
      ASSERT_TRUE(own.ok());
      EXPECT_GT(own.iterations(), 2);
      EXPECT_EQ(with_shared.status, own.status);
      EXPECT_EQ(with_shared.weights, own.weights);
      EXPECT_EQ(with_shared.policy, own.policy);
      EXPECT_EQ(with_shared.b, own.b);
      EXPECT_EQ(Eigen::MatrixXd(with_shared.a), Eigen::MatrixXd(own.a));
      ASSERT_EQ(with_shared.iterations(), own.iterations());
      for (int i = 0; i < own.iterations(); ++i) {
        EXPECT_EQ(with_shared.history[i].policy_changes, own.history[i].policy_changes);
        EXPECT_EQ(with_shared.history[i].rcond, own.history[i].rcond);
      }
    }
  }
  const SampleBatch copy = samples;  // equal, but not the samples the part was made for
  EXPECT_THROW(fit_lspi_copy_basis(state_kernels, 2, copy, {}, shared), std::invalid_argument);
  const SparseRowMatrix other = state_kernels;
  EXPECT_THROW(fit_lspi_copy_basis(other, 2, samples, {}, shared), std::invalid_argument);
  EXPECT_THROW(fit_lspi_copy_basis(state_kernels, 3, samples, {}, shared), std::invalid_argument);
  SparseRowMatrix uncompressed = state_kernels;
  uncompressed.uncompress();
  EXPECT_THROW(ActionBlockSystem::copy_basis_fixed(uncompressed, 2, samples),
               std::invalid_argument);
  SampleBatch outside;
  outside.add(kStates, 0, 0.0, 1, false);  // a state past the kernels' rows
  EXPECT_THROW(ActionBlockSystem::copy_basis_fixed(state_kernels, 2, outside),
               std::invalid_argument);
}

// States that share their kernels (the Khepera's readings of one SOM unit under
// proto-value functions): the fit from the distinct rows and a row per state equals
// the fit on the expanded kernels bit for bit, policy per state and policy_changes
// counting states included, BRM and LSTD-Q, dense rows and rows with zeros (an
// eigenvector's exact zeros), 60 states on 13 rows in shuffled order.
TEST(Lspi, CopyBasisFromSharedRowsEqualsTheExpandedKernels) {
  constexpr int kStates = 60, kRows = 12, kCenters = 5;
  // Blocks of five neighbouring states share a row (rows in a shuffled order);
  // Gaussian bumps over the blocks, cut below 0.05 (exact zeros).
  const std::vector<std::int32_t> shuffled = {7, 2, 11, 0, 5, 9, 1, 4, 10, 3, 8, 6};
  std::vector<std::int32_t> row_of_state(kStates);
  for (int s = 0; s < kStates; ++s) row_of_state[s] = shuffled[static_cast<std::size_t>(s / 5)];
  std::vector<Eigen::Triplet<double>> row_entries;
  for (int block = 0; block < kRows; ++block) {
    for (int j = 0; j < kCenters; ++j) {
      const double d = block - 2.75 * j;
      const double value = std::exp(-d * d / 4.0);
      if (value >= 0.05)
        row_entries.emplace_back(shuffled[static_cast<std::size_t>(block)], j, value);
    }
  }
  SparseRowMatrix rows(kRows, kCenters);
  rows.setFromTriplets(row_entries.begin(), row_entries.end());
  rows.makeCompressed();
  std::vector<Eigen::Triplet<double>> entries;
  for (int s = 0; s < kStates; ++s) {
    for (SparseRowMatrix::InnerIterator it(rows, row_of_state[s]); it; ++it) {
      entries.emplace_back(s, it.col(), it.value());
    }
  }
  SparseRowMatrix expanded(kStates, kCenters);
  expanded.setFromTriplets(entries.begin(), entries.end());
  expanded.makeCompressed();
  const SampleBatch samples = random_chain_walk(kStates, 20000, 19);
  for (const LspiSolver solver : {LspiSolver::brm, LspiSolver::lstdq}) {
    LspiOptions options;
    options.solver = solver;
    options.ridge = 1e-6;
    const LspiResult full = fit_lspi_copy_basis(expanded, 2, samples, options);
    const LspiResult shared = fit_lspi_copy_basis(rows, row_of_state, 2, samples, options);
    ASSERT_TRUE(full.ok());
    EXPECT_EQ(shared.status, full.status);
    EXPECT_EQ(shared.weights, full.weights);
    EXPECT_EQ(shared.policy, full.policy);
    EXPECT_EQ(shared.b, full.b);
    EXPECT_EQ(Eigen::MatrixXd(shared.a), Eigen::MatrixXd(full.a));
    ASSERT_EQ(shared.iterations(), full.iterations());
    for (int i = 0; i < full.iterations(); ++i) {
      EXPECT_EQ(shared.history[i].policy_changes, full.history[i].policy_changes) << i;
      EXPECT_EQ(shared.history[i].weight_change, full.history[i].weight_change) << i;
    }
    // States, not rows, are counted: a row's change counts its five states.
    EXPECT_GT(full.iterations(), 2);
    EXPECT_GT(full.history.front().policy_changes, 0);
    for (const LspiIteration& iteration : shared.history)
      EXPECT_EQ(iteration.policy_changes % 5, 0);
  }
  std::vector<std::int32_t> outside = row_of_state;
  outside[5] = kRows;
  EXPECT_THROW(fit_lspi_copy_basis(rows, outside, 2, samples, {}), std::invalid_argument);
  std::vector<std::int32_t> orphan(kStates, 0);  // rows 1 .. 12 belong to no state
  EXPECT_THROW(fit_lspi_copy_basis(rows, orphan, 2, samples, {}), std::invalid_argument);
}

// The copy-basis greedy policy reads only action 0's rows but sums the same
// products in the same order: near-tied Q values (weights equal in all but the last
// bits, many exact ties) give the same policy as greedy_policy.
TEST(Lspi, CopyLayoutGreedyPolicyEqualsTheSparseProduct) {
  RandomStream rng(41, 0, 0);
  constexpr std::int32_t kStates = 500, kCenters = 9, kActions = 4;
  std::vector<Eigen::Triplet<double>> entries;
  for (std::int32_t s = 0; s < kStates; ++s) {
    for (std::int32_t j = 0; j < kCenters; ++j) {
      if (rng.uniform() < 0.3) entries.emplace_back(s, j, rng.uniform());
    }
  }
  SparseRowMatrix state_kernels(kStates, kCenters);
  state_kernels.setFromTriplets(entries.begin(), entries.end());
  const SparseRowMatrix features = copy_basis(state_kernels, kActions);
  ASSERT_TRUE(is_copy_layout(features, kActions));
  for (int trial = 0; trial < 20; ++trial) {
    Eigen::VectorXd w(kCenters * kActions);
    for (Eigen::Index j = 0; j < kCenters; ++j) {
      const double base = rng.uniform(-1, 1);
      for (std::int32_t a = 0; a < kActions; ++a) {
        w(a * kCenters + j) =
            trial % 2 == 0 ? base
                           : base * (1.0 + 1e-15 * static_cast<double>(rng.uniform_index(3)));
      }
    }
    EXPECT_EQ(copy_layout_greedy_policy(features, kActions, w),
              greedy_policy(features, kActions, w))
        << "trial " << trial;
  }
  // A shift-like table (rows of different actions differ) is not a copy layout.
  SparseRowMatrix other = features;
  other.coeffRef(kActions + 1, kCenters) += 1.0;
  other.makeCompressed();
  EXPECT_FALSE(is_copy_layout(other, kActions));
}

// Lagoudakis & Parr's rule: stop when ||w_k - w_{k-1}|| <= epsilon. Once the greedy
// policy repeats, the next system (and so the next w) is the same bit for bit, so
// with epsilon = 0 the weights rule stops exactly one evaluation after the policy
// rule, with the same weights and policy. Every iteration records the weight change
// and, with keep_iterates, its weights.
TEST(Lspi, WeightChangeRuleStopsOneEvaluationAfterThePolicyRule) {
  for (const LspiSolver solver : {LspiSolver::brm, LspiSolver::lstdq}) {
    for (std::uint64_t seed = 1; seed <= 5; ++seed) {
      const TabularMdp mdp = random_mdp(20, 4, true, true, seed);
      const SparseRowMatrix features = tabular_features(20, 4);
      LspiOptions options;
      options.solver = solver;
      options.max_iterations = 100;
      options.keep_iterates = true;
      const LspiResult by_policy = fit_lspi(features, 4, full_coverage_samples(mdp), options);
      options.stopping = LspiStopping::weights_converged;
      options.weight_tolerance = 0.0;
      const LspiResult by_weights = fit_lspi(features, 4, full_coverage_samples(mdp), options);
      ASSERT_EQ(by_policy.status, LspiStatus::converged);
      ASSERT_EQ(by_weights.status, LspiStatus::converged);
      EXPECT_EQ(by_weights.iterations(), by_policy.iterations() + 1) << "seed " << seed;
      EXPECT_EQ(by_weights.history.back().weight_change, 0.0);
      EXPECT_EQ(by_weights.policy, by_policy.policy);
      EXPECT_EQ(by_weights.weights, by_policy.weights);
      for (const LspiResult* result : {&by_policy, &by_weights}) {
        ASSERT_EQ(result->iterates.size(), result->history.size());
        EXPECT_EQ(result->iterates.back(), result->weights);
        EXPECT_EQ(result->history[0].weight_change, result->iterates[0].norm());
        for (std::size_t i = 1; i < result->iterates.size(); ++i) {
          EXPECT_EQ(result->history[i].weight_change,
                    (result->iterates[i] - result->iterates[i - 1]).norm());
        }
      }
    }
  }
}

TEST(Lspi, WeightChangeRuleWithALargeToleranceStopsAfterOneEvaluation) {
  const TabularMdp mdp = random_mdp(20, 4, true, true, 3);
  LspiOptions options;
  options.stopping = LspiStopping::weights_converged;
  options.weight_tolerance = 1e300;
  const LspiResult result =
      fit_lspi(tabular_features(20, 4), 4, full_coverage_samples(mdp), options);
  EXPECT_EQ(result.status, LspiStatus::converged);
  EXPECT_EQ(result.iterations(), 1);
  EXPECT_TRUE(result.iterates.empty());  // keep_iterates is off
  options.weight_tolerance = -1.0;
  EXPECT_THROW(fit_lspi(tabular_features(20, 4), 4, full_coverage_samples(mdp), options),
               std::invalid_argument);
}

}  // namespace
}  // namespace ggk::kernels
