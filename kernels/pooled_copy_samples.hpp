#pragma once
// The copy basis's samples pooled by what each block of the LSPI system reads,
// for states that share kernel rows (the Khepera's 20,000 readings take the rows
// of at most ~700 SOM units: fit_lspi_pooled_copy_basis in lspi.hpp).
//
// In the copy scheme kappa(s, a) = kappa(s) for every a, so with the samples in
// the rows' terms (u_i the row of s_i, u'_i that of s'_i) the blocks of the
// action-block system (action_block_system.hpp) are
//   D_x  = sum_{a_i = x} w_i k(u_i) k(u_i)^T
//   C_xy = sum_{a_i = x, pi(u'_i) = y} w_i k(u_i) k(u'_i)^T
//   E_y  = sum_{pi(u'_i) = y} w_i k(u'_i) k(u'_i)^T
// and the right-hand side's parts sum_{a_i = x} w_i r_i k(u_i) and
// sum_{pi(u'_i) = y} w_i r_i k(u'_i). D and the first part depend on a sample only
// through (u_i, a_i); C, E and the second part, summed over the non-terminal
// samples of one (a_i, u'_i), only through
//   W = sum w_i,  g = sum w_i k(u_i),  R = sum w_i r_i
// since C's terms are then g k(u')^T and E's W k(u') k(u')^T. So:
// - `by_start` folds the samples by (u, a): weight W, reward R / W (terminal: it
//   feeds D and the first part only);
// - `by_successor` has one sample per (a, u') with a successor: state R_rows + j
//   (row j of the pooled start vectors), weight W, reward R / W, successor u';
// - `table` is the kernels (rows 0 .. R_rows - 1) then g_j / W_j: a system that
//   gathers sqrt(W) (g / W) and sqrt(W) k(u') sums g k(u')^T, W k k^T and R k.
// The sums are the same in exact arithmetic; in floating point they run in
// another order (and through g / W, sqrt(W)^2 = W up to rounding), a few ulps of
// the summed magnitudes (tests/kernels/pooled_copy_samples_test.cpp bounds them).
// The products shrink from n samples to the distinct (u, a) and (a, u') pairs:
// the Khepera's 20,000 readings to ~2,700 and ~2,600.
//
// Entries stay exactly zero where they were: g_j's entry c is zero when every
// k(u_i) it sums is zero there (all weights are positive), so no group reaches an
// entry of C that none of its samples reached.
//
// Thread-safety: reentrant.

#include <cstdint>

#include "kernels/eigen_types.hpp"
#include "kernels/sample_batch.hpp"

namespace ggk::kernels {

struct PooledCopySamples {
  SparseRowMatrix table;  // the kernels' rows, then one row g_j / W_j per pooled successor sample
  SampleBatch by_start;
  SampleBatch by_successor;
};

// `samples` in the rows' terms (states and successors are rows of `kernels`,
// compressed, R x p), valid for R states and num_actions actions (checked by the
// caller). Pooled in the order of first occurrence, each sum in sample order:
// deterministic.
PooledCopySamples pool_copy_samples(const SparseRowMatrix& kernels, std::int32_t num_actions,
                                    const SampleBatch& samples);

}  // namespace ggk::kernels
