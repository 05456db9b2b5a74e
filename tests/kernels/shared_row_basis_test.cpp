#include "kernels/shared_row_basis.hpp"

#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

#include "kernels/lspi.hpp"
#include "kernels/random_stream.hpp"
#include "kernels/state_action_basis.hpp"
#include "support/near_tied_weights.hpp"

namespace ggk::kernels {
namespace {

constexpr int kGridWidth = 12, kGridHeight = 9, kGridStates = kGridWidth * kGridHeight,
              kGridActions = 4;

// A grid world with walls at the border (a move into one stays put): deterministic,
// as the arm is.
int grid_move(int s, int a) {
  const int x = s % kGridWidth, y = s / kGridWidth;
  const int dx[kGridActions] = {1, -1, 0, 0}, dy[kGridActions] = {0, 0, 1, -1};
  const int nx = x + dx[a], ny = y + dy[a];
  if (nx < 0 || nx >= kGridWidth || ny < 0 || ny >= kGridHeight) return s;
  return ny * kGridWidth + nx;
}

// Gaussian kernels on the grid's coordinates around `centers` centres, cut below
// `truncation` (exact zeros: rows with fewer than p entries) when it is positive.
SparseRowMatrix grid_kernels(int centers, double truncation) {
  std::vector<Eigen::Triplet<double>> entries;
  for (int s = 0; s < kGridStates; ++s) {
    for (int j = 0; j < centers; ++j) {
      const int c = (j * 37) % kGridStates;
      const double dx = s % kGridWidth - c % kGridWidth, dy = s / kGridWidth - c / kGridWidth;
      const double value = std::exp(-(dx * dx + dy * dy) / 18.0);
      if (truncation <= 0.0 || value >= truncation) entries.emplace_back(s, j, value);
    }
  }
  SparseRowMatrix kernels(kGridStates, centers);
  kernels.setFromTriplets(entries.begin(), entries.end());
  kernels.makeCompressed();
  return kernels;
}

// Random actions from random starts; the far corner is a terminal goal; state 0
// never takes action 2 and state 5 never action 0 (pairs the model does not
// observe: the copy fallback).
SampleBatch grid_walk(int steps, std::uint64_t seed) {
  RandomStream rng(seed, 0, 0);
  SampleBatch batch;
  int s = static_cast<int>(rng.uniform_index(kGridStates));
  for (int t = 0; t < steps; ++t) {
    const int a = static_cast<int>(rng.uniform_index(kGridActions));
    if ((s == 0 && a == 2) || (s == 5 && a == 0)) continue;
    const int next = grid_move(s, a);
    const bool goal = next == kGridStates - 1;
    batch.add(s, a, goal ? 1.0 : -0.01, next, goal);
    s = goal || rng.uniform_index(20) == 0 ? static_cast<int>(rng.uniform_index(kGridStates))
                                           : next;
  }
  return batch;
}

EmpiricalTransitionModel grid_model(const SampleBatch& batch) {
  return EmpiricalTransitionModel(kGridStates, kGridActions, batch.states, batch.actions,
                                  batch.next_states);
}

bool identical_bits(double a, double b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}

void expect_identical_table(const SparseRowMatrix& actual, const SparseRowMatrix& expected) {
  ASSERT_EQ(actual.rows(), expected.rows());
  ASSERT_EQ(actual.cols(), expected.cols());
  ASSERT_EQ(actual.nonZeros(), expected.nonZeros());
  for (Eigen::Index row = 0; row < expected.rows(); ++row) {
    SparseRowMatrix::InnerIterator it(actual, row);
    for (SparseRowMatrix::InnerIterator want(expected, row); want; ++want, ++it) {
      ASSERT_TRUE(it) << "row " << row;
      EXPECT_EQ(it.col(), want.col()) << "row " << row;
      EXPECT_TRUE(identical_bits(it.value(), want.value())) << "row " << row;
    }
    EXPECT_FALSE(it) << "row " << row;
  }
}

// A deterministic model's shift table is its successors' kernel rows (the
// unobserved pairs' own rows), value for value: dense and truncated kernels.
TEST(SharedRowBasis, DeterministicShiftTableIsTheSuccessorsRows) {
  const SampleBatch batch = grid_walk(4000, 3);
  const EmpiricalTransitionModel model = grid_model(batch);
  ASSERT_FALSE(model.observed(0, 2));
  for (const double truncation : {0.0, 0.2}) {
    const SparseRowMatrix kernels = grid_kernels(10, truncation);
    const auto rows = shift_basis_rows(kernels, kGridActions, model);
    ASSERT_TRUE(rows.has_value());
    EXPECT_EQ((*rows)[0 * kGridActions + 2], 0);  // unobserved: its own row
    EXPECT_EQ((*rows)[0 * kGridActions + 0], 1);  // observed: the successor's
    expect_identical_table(shared_row_table(kernels, *rows, kGridActions),
                           shift_basis(kernels, kGridActions, model));
  }
  const std::vector<std::int32_t> copy = copy_basis_rows(kGridStates, kGridActions);
  const SparseRowMatrix kernels = grid_kernels(10, 0.2);
  expect_identical_table(shared_row_table(kernels, copy, kGridActions),
                         copy_basis(kernels, kGridActions));
}

// Where the shift table is not made of kernel rows there are no rows: a pair with
// two successors, and a kernel value -0 (0 + 1 (-0) is +0 in the table). A model
// of other states or actions is refused as shift_basis refuses it.
TEST(SharedRowBasis, NoRowsWhereTheShiftTableIsNotMadeOfKernelRows) {
  SampleBatch batch = grid_walk(2000, 5);
  const SparseRowMatrix kernels = grid_kernels(10, 0.0);
  ASSERT_TRUE(shift_basis_rows(kernels, kGridActions, grid_model(batch)).has_value());
  SampleBatch stochastic = batch;
  stochastic.add(3, 1, 0.0, 40, false);  // (3, 1) also leads to 40
  EXPECT_FALSE(shift_basis_rows(kernels, kGridActions, grid_model(stochastic)).has_value());
  SparseRowMatrix negative_zero = kernels;
  negative_zero.valuePtr()[7] = -0.0;
  EXPECT_FALSE(shift_basis_rows(negative_zero, kGridActions, grid_model(batch)).has_value());
  const EmpiricalTransitionModel three_actions(kGridStates, 3, {}, {}, {});
  EXPECT_THROW(shift_basis_rows(kernels, kGridActions, three_actions), std::invalid_argument);
  const std::vector<std::int32_t> outside(kGridStates * kGridActions, kGridStates);
  EXPECT_THROW(shared_row_table(kernels, outside, kGridActions), std::invalid_argument);
  const std::vector<std::int32_t> ragged(kGridActions + 1, 0);
  EXPECT_THROW(shared_row_table(kernels, ragged, kGridActions), std::invalid_argument);
}

// The greedy step and the state values read through the index equal the table's
// (greedy_policy, state_values) bit for bit, on near-tied weights (ties and
// differences in the last bits), dense and truncated kernels.
TEST(SharedRowBasis, GreedyPolicyAndValuesEqualTheTables) {
  const EmpiricalTransitionModel model = grid_model(grid_walk(4000, 7));
  RandomStream rng(11, 0, 0);
  for (const double truncation : {0.0, 0.3}) {
    const SparseRowMatrix kernels = grid_kernels(16, truncation);
    const std::vector<std::int32_t> rows = *shift_basis_rows(kernels, kGridActions, model);
    const SparseRowMatrix table = shift_basis(kernels, kGridActions, model);
    for (int trial = 0; trial < 6; ++trial) {
      const Eigen::VectorXd w = test_support::near_tied_weights(rng, 16, kGridActions, trial);
      EXPECT_EQ(shared_row_greedy(kernels, rows, kGridActions, w),
                greedy_policy(table, kGridActions, w));
      const Eigen::VectorXd values = shared_row_state_values(kernels, rows, kGridActions, w);
      const Eigen::VectorXd expected = state_values(table, kGridActions, w);
      ASSERT_EQ(values.size(), expected.size());
      for (Eigen::Index s = 0; s < values.size(); ++s) {
        EXPECT_TRUE(identical_bits(values(s), expected(s))) << "state " << s << " trial " << trial;
      }
    }
  }
}

// fit_lspi_shared_rows equals fit_lspi on the shift table bit for bit (weights,
// policy, A, b, history), BRM and LSTD-Q, dense and truncated kernels, over
// enough iterations for the system's rank-r updates; on the copy rows it equals
// fit_lspi_copy_basis.
TEST(SharedRowBasis, FitEqualsTheFitOnTheTable) {
  const SampleBatch samples = grid_walk(6000, 13);
  const EmpiricalTransitionModel model = grid_model(samples);
  for (const double truncation : {0.0, 0.1}) {
    const SparseRowMatrix kernels = grid_kernels(24, truncation);
    const std::vector<std::int32_t> rows = *shift_basis_rows(kernels, kGridActions, model);
    const SparseRowMatrix table = shift_basis(kernels, kGridActions, model);
    for (const LspiSolver solver : {LspiSolver::brm, LspiSolver::lstdq}) {
      LspiOptions options;
      options.solver = solver;
      options.ridge = 1e-6;
      options.keep_iterates = true;
      const LspiResult expected = fit_lspi(table, kGridActions, samples, options);
      const LspiResult shared = fit_lspi_shared_rows(kernels, rows, kGridActions, samples, options);
      ASSERT_TRUE(expected.ok()) << expected.message;
      EXPECT_GT(expected.iterations(), 2);
      EXPECT_EQ(shared.status, expected.status);
      EXPECT_EQ(shared.weights, expected.weights);
      EXPECT_EQ(shared.policy, expected.policy);
      EXPECT_EQ(shared.b, expected.b);
      EXPECT_EQ(Eigen::MatrixXd(shared.a), Eigen::MatrixXd(expected.a));
      EXPECT_EQ(shared.iterates, expected.iterates);
      ASSERT_EQ(shared.iterations(), expected.iterations());
      for (int i = 0; i < expected.iterations(); ++i) {
        EXPECT_EQ(shared.history[i].policy_changes, expected.history[i].policy_changes) << i;
        EXPECT_EQ(shared.history[i].weight_change, expected.history[i].weight_change) << i;
        EXPECT_EQ(shared.history[i].rcond, expected.history[i].rcond) << i;
      }
      const LspiResult copy = fit_lspi_shared_rows(
          kernels, copy_basis_rows(kGridStates, kGridActions), kGridActions, samples, options);
      const LspiResult copy_expected = fit_lspi_copy_basis(kernels, kGridActions, samples, options);
      EXPECT_EQ(copy.weights, copy_expected.weights);
      EXPECT_EQ(copy.policy, copy_expected.policy);
      EXPECT_EQ(copy.iterations(), copy_expected.iterations());
    }
  }
  const SparseRowMatrix kernels = grid_kernels(8, 0.0);
  SampleBatch outside;
  outside.add(kGridStates, 0, 0.0, 1, false);
  EXPECT_THROW(fit_lspi_shared_rows(kernels, copy_basis_rows(kGridStates, kGridActions),
                                    kGridActions, outside, {}),
               std::invalid_argument);
  const std::vector<std::int32_t> outside_rows(kGridStates * kGridActions, -1);
  EXPECT_THROW(fit_lspi_shared_rows(kernels, outside_rows, kGridActions, samples, {}),
               std::invalid_argument);
}

}  // namespace
}  // namespace ggk::kernels
