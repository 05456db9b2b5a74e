#pragma once
// State-action tables made of state-kernel rows: row s m + a of the (N m) x (m p)
// table (action-block form, state_action_basis.hpp) is row row_of_pair[s m + a] of
// the state kernels (R x p), moved into block a. Two schemes' tables are such:
// - the copy scheme's, row_of_pair[s m + a] = s (copy_basis_rows);
// - the shift scheme's where the empirical model is deterministic, as the arm's is
//   (every observed pair has one successor): P(s' | s, a) = 1 and 0 + 1 K(s', c_j)
//   is K(s', c_j), so the row is the successor's (shift_basis_rows), and an
//   unobserved pair's the state's own (the copy fallback).
// fit_lspi_shared_rows (lspi.hpp) and the two functions below read the kernels
// through the index instead of the table: R p values instead of N m p (the arm:
// 1.66 MB instead of 6.6 MB at p = 128), and no table to build. Q(s, a) is the
// dot product of a kernel row with block a of w: computed once per row and action
// (copy_action_values), then looked up.
//
// Thread-safety: reentrant.

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "kernels/eigen_types.hpp"
#include "kernels/transition_model.hpp"

namespace ggk::kernels {

// row_of_pair of the copy scheme for num_states states.
std::vector<std::int32_t> copy_basis_rows(std::int32_t num_states, std::int32_t num_actions);

// row_of_pair whose table is shift_basis(state_kernels, num_actions, model) value for
// value, bit for bit; nullopt where there is none: a pair with several successors
// or a probability other than 1 (a stochastic model), or a kernel value -0 (which
// 0 + 1 K turns into +0). std::invalid_argument where shift_basis throws.
std::optional<std::vector<std::int32_t>> shift_basis_rows(const SparseRowMatrix& state_kernels,
                                                          std::int32_t num_actions,
                                                          const EmpiricalTransitionModel& model);

// Throws std::invalid_argument, naming `caller`, unless the kernels are compressed,
// row_of_pair's size is a multiple of num_actions and every row is one of the kernels'.
void check_shared_rows(const SparseRowMatrix& kernels, std::span<const std::int32_t> row_of_pair,
                       std::int32_t num_actions, const char* caller);

// The table itself (for tests and for callers that need it formed). Here and
// below, the input is checked as check_shared_rows does.
SparseRowMatrix shared_row_table(const SparseRowMatrix& kernels,
                                 std::span<const std::int32_t> row_of_pair,
                                 std::int32_t num_actions);

// greedy_policy(shared_row_table(...), num_actions, weights), bit for bit (the same
// Q doubles, the same first largest); weights of size m p.
std::vector<std::int32_t> shared_row_greedy(const SparseRowMatrix& kernels,
                                            std::span<const std::int32_t> row_of_pair,
                                            std::int32_t num_actions,
                                            const Eigen::VectorXd& weights);

// state_values(shared_row_table(...), num_actions, weights), bit for bit.
Eigen::VectorXd shared_row_state_values(const SparseRowMatrix& kernels,
                                        std::span<const std::int32_t> row_of_pair,
                                        std::int32_t num_actions, const Eigen::VectorXd& weights);

}  // namespace ggk::kernels
