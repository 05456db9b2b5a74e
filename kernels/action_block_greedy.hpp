#pragma once
// The greedy step of LSPI for a table in action-block form (lspi.hpp: row s m + a
// holds phi(s, a), zero outside columns [a p, (a + 1) p)), such as the shift basis
// (state_action_basis.hpp): the policy of greedy_policy(features, m, w), bit for
// bit, without forming features * w.
//
// greedy_policy sums each Q(s, a) as Eigen's sparse-dense product does: from 0, the
// row's entries in storage order, one rounded multiply and one rounded add each
// (no fused multiply-add), then 0 + 1 * sum (which changes at most a zero's sign,
// and no comparison sees that). Its loop carries one sum at a time and reads every
// entry's column index. Here a state whose m rows are dense (p entries each, the
// whole block) sums its m actions side by side, each in entry order, with the
// columns implied; other states take the row loop. So each Q is the same double,
// and the argmax (the first largest, ties to the lowest action) the same action.
// bench/lspi_benchmark.cpp, BM_ActionBlockGreedy, times both.
//
// Thread-safety: reentrant.

#include <cstdint>
#include <vector>

#include "kernels/eigen_types.hpp"

namespace ggk::kernels {

// features: (N m) x (m p), compressed, in action-block form (the caller checks it:
// fit_lspi does); weights of size m p. The greedy action per state.
std::vector<std::int32_t> action_block_greedy(const SparseRowMatrix& features,
                                              std::int32_t num_actions,
                                              const Eigen::VectorXd& weights);

}  // namespace ggk::kernels
