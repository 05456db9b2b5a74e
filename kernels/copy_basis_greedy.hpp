#pragma once
// The greedy step of LSPI for a copy basis (state_action_basis.hpp), read from the
// state kernels alone: row s * row_step of `kernels` holds kappa(s) (p columns), and
// Q(s, a) = sum_j kappa_j(s) w[a p + j]. Each Q(s, a) sums the products of the row's
// entries in entry order, one rounded multiply and one rounded add per entry (no
// fused multiply-add), as the sparse product features * w does for row s * m + a of
// the copy table: the values, and so the policy (ties to the lowest action), are bit
// for bit greedy_policy's (lspi.hpp).
//
// The step reads the whole table once per LSPI iteration and is compute bound where
// the table's rows are dense (untruncated kernels, proto-value functions): on
// x86-64 CPUs with AVX2, four actions of eight dense rows go through 256-bit
// multiplies and adds, one lane per action (bench/lspi_benchmark.cpp,
// BM_CopyBasisGreedy, measures both paths). Lane arithmetic is the same IEEE
// multiply and add as the portable path's, so the two give the same bits; the
// path is chosen at run time (the CPU's flags, kernels/avx2_dispatch.hpp), never
// by the build.
//
// Thread-safety: reentrant.

#include <cstdint>
#include <vector>

#include "kernels/eigen_types.hpp"

namespace ggk::kernels {

// automatic: the AVX2 path where the CPU has it (cpu_has_avx2) and m = 4, else the
// portable one.
enum class GreedyInstructions { automatic, portable };

// The greedy action per state (kernels.rows() / row_step states), kernels
// compressed, weights of size p * num_actions.
std::vector<std::int32_t> copy_greedy(
    const SparseRowMatrix& kernels, Eigen::Index row_step, Eigen::Index p, std::int32_t num_actions,
    const Eigen::VectorXd& weights,
    GreedyInstructions instructions = GreedyInstructions::automatic);

// The Q values the greedy step compares: row s holds Q(s, 0 .. m) (kernels.rows() /
// row_step rows), each the same double as action_values(copy table, weights) gives
// for row s m + a (for shared_row_basis.hpp's tables, which look them up).
RowMatrixXd copy_action_values(const SparseRowMatrix& kernels, Eigen::Index row_step,
                               Eigen::Index p, std::int32_t num_actions,
                               const Eigen::VectorXd& weights,
                               GreedyInstructions instructions = GreedyInstructions::automatic);

}  // namespace ggk::kernels
