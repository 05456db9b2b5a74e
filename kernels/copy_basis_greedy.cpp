#include "kernels/copy_basis_greedy.hpp"

#include <algorithm>

#include "kernels/avx2_dispatch.hpp"
#include "kernels/first_best.hpp"

namespace ggk::kernels {

namespace {

// Points v[b] at the values of state first + b's row, b < kLanes; true when every
// one of those rows is dense (p entries, columns 0 .. p - 1 in order).
template <std::size_t kLanes>
bool dense_block(const SparseRowMatrix& kernels, Eigen::Index row_step, std::size_t first,
                 std::int64_t p, const double* (&v)[kLanes]) {
  const auto* outer = kernels.outerIndexPtr();
  bool dense = true;
  for (std::size_t b = 0; b < kLanes; ++b) {
    const auto row = static_cast<Eigen::Index>(first + b) * row_step;
    dense = dense && outer[row + 1] - outer[row] == p;
    v[b] = kernels.valuePtr() + outer[row];
  }
  return dense;
}

// The Q values of states [first, last), one state at a time, for m = kActions
// actions (any m when kActions is 0), each handed to emit(s, q) (q[0 .. m)). A
// fixed-size local array stays in registers; each action's sum runs in entry order.
template <std::int32_t kActions, class Emit>
void copy_q_states(const SparseRowMatrix& kernels, Eigen::Index row_step, std::int32_t num_actions,
                   const std::vector<double>& by_center, std::size_t first, std::size_t last,
                   const Emit& emit) {
  const std::int32_t m = kActions > 0 ? kActions : num_actions;
  const auto* outer = kernels.outerIndexPtr();
  const auto* inner = kernels.innerIndexPtr();
  const double* values = kernels.valuePtr();
  std::vector<double> q_storage(kActions > 0 ? 0 : static_cast<std::size_t>(m));
  for (std::size_t s = first; s < last; ++s) {
    const auto row = static_cast<Eigen::Index>(s) * row_step;
    double q_fixed[kActions > 0 ? kActions : 1] = {};
    double* q = kActions > 0 ? q_fixed : q_storage.data();
    if constexpr (kActions <= 0) std::fill(q_storage.begin(), q_storage.end(), 0.0);
    for (auto e = outer[row]; e < outer[row + 1]; ++e) {
      const double v = values[e];
      const double* w = by_center.data() + static_cast<std::size_t>(inner[e]) * m;
      for (std::int32_t a = 0; a < m; ++a) q[a] += v * w[a];
    }
    emit(s, static_cast<const double*>(q));
  }
}

// The portable path: with a fixed action count, four states at a time where all
// four rows are dense (p entries: columns 0 .. p - 1 in order): four independent
// sums per action in flight instead of one chain of dependent additions; each sums
// the same products in the same order.
template <std::int32_t kActions, class Emit>
void copy_q_rows(const SparseRowMatrix& kernels, Eigen::Index row_step, std::int32_t num_actions,
                 const std::vector<double>& by_center, std::size_t num_states, const Emit& emit) {
  std::size_t s = 0;
  if constexpr (kActions > 0) {
    const auto p = static_cast<std::int64_t>(by_center.size()) / kActions;
    constexpr std::size_t kLanes = 4;
    for (; s + kLanes <= num_states; s += kLanes) {
      const double* v[kLanes];
      if (!dense_block(kernels, row_step, s, p, v)) {
        copy_q_states<kActions>(kernels, row_step, num_actions, by_center, s, s + kLanes, emit);
        continue;
      }
      double q[kLanes][kActions] = {};
      for (std::int64_t j = 0; j < p; ++j) {
        const double* w = by_center.data() + j * kActions;
        for (std::size_t b = 0; b < kLanes; ++b) {
          for (std::int32_t a = 0; a < kActions; ++a) q[b][a] += v[b][j] * w[a];
        }
      }
      for (std::size_t b = 0; b < kLanes; ++b) emit(s + b, static_cast<const double*>(q[b]));
    }
  }
  copy_q_states<kActions>(kernels, row_step, num_actions, by_center, s, num_states, emit);
}

#if GGK_AVX2_DISPATCH
// The AVX2 path for four actions: eight states at a time where all eight rows are
// dense (p entries, columns 0 .. p - 1 in order), one 256-bit lane per action, a
// multiply then an add per entry (the target has no FMA, so none is fused): each
// Q(s, a) is the portable path's sum, term by term. Other rows go through the
// portable path's per-state loop.
template <class Emit>
__attribute__((target("avx2"))) void copy_q_rows_avx2(const SparseRowMatrix& kernels,
                                                      Eigen::Index row_step,
                                                      const std::vector<double>& by_center,
                                                      std::size_t num_states, const Emit& emit) {
  constexpr std::size_t kLanes = 8;
  const auto p = static_cast<std::int64_t>(by_center.size()) / 4;
  std::size_t s = 0;
  for (; s + kLanes <= num_states; s += kLanes) {
    const double* v[kLanes];
    if (!dense_block(kernels, row_step, s, p, v)) {
      copy_q_states<4>(kernels, row_step, 4, by_center, s, s + kLanes, emit);
      continue;
    }
    __m256d q[kLanes];
    for (std::size_t b = 0; b < kLanes; ++b) q[b] = _mm256_setzero_pd();
    for (std::int64_t j = 0; j < p; ++j) {
      const __m256d w = _mm256_loadu_pd(by_center.data() + j * 4);
      for (std::size_t b = 0; b < kLanes; ++b) {
        q[b] = _mm256_add_pd(q[b], _mm256_mul_pd(_mm256_set1_pd(v[b][j]), w));
      }
    }
    for (std::size_t b = 0; b < kLanes; ++b) {
      alignas(32) double lane[4];
      _mm256_store_pd(lane, q[b]);
      emit(s + b, static_cast<const double*>(lane));
    }
  }
  copy_q_states<4>(kernels, row_step, 4, by_center, s, num_states, emit);
}
#endif

// Q(s, .) of every state, handed to emit(s, q) (q[0 .. m)), on the path
// `instructions` picks. The weights are read centre-major (w[a p + j] at j m + a)
// so one entry serves all actions.
template <class Emit>
void for_each_copy_q(const SparseRowMatrix& kernels, Eigen::Index row_step, Eigen::Index p,
                     std::int32_t num_actions, const Eigen::VectorXd& weights,
                     GreedyInstructions instructions, const Emit& emit) {
  std::vector<double> by_center(static_cast<std::size_t>(p * num_actions));
  for (Eigen::Index j = 0; j < p; ++j) {
    for (std::int32_t a = 0; a < num_actions; ++a) {
      by_center[static_cast<std::size_t>(j * num_actions + a)] = weights(a * p + j);
    }
  }
  const auto num_states = static_cast<std::size_t>(kernels.rows() / row_step);
  switch (num_actions) {
    case 2:
      copy_q_rows<2>(kernels, row_step, num_actions, by_center, num_states, emit);
      break;
    case 4:
#if GGK_AVX2_DISPATCH
      if (instructions == GreedyInstructions::automatic && cpu_has_avx2()) {
        copy_q_rows_avx2(kernels, row_step, by_center, num_states, emit);
        break;
      }
#endif
      copy_q_rows<4>(kernels, row_step, num_actions, by_center, num_states, emit);
      break;
    default:
      copy_q_rows<0>(kernels, row_step, num_actions, by_center, num_states, emit);
  }
}

}  // namespace

std::vector<std::int32_t> copy_greedy(const SparseRowMatrix& kernels, Eigen::Index row_step,
                                      Eigen::Index p, std::int32_t num_actions,
                                      const Eigen::VectorXd& weights,
                                      GreedyInstructions instructions) {
  std::vector<std::int32_t> policy(static_cast<std::size_t>(kernels.rows() / row_step), 0);
  for_each_copy_q(kernels, row_step, p, num_actions, weights, instructions,
                  [&](std::size_t s, const double* q) { policy[s] = first_best(q, num_actions); });
  return policy;
}

RowMatrixXd copy_action_values(const SparseRowMatrix& kernels, Eigen::Index row_step,
                               Eigen::Index p, std::int32_t num_actions,
                               const Eigen::VectorXd& weights, GreedyInstructions instructions) {
  RowMatrixXd values(kernels.rows() / row_step, num_actions);
  double* out = values.data();
  for_each_copy_q(kernels, row_step, p, num_actions, weights, instructions,
                  [&](std::size_t s, const double* q) {
                    std::copy(q, q + num_actions, out + s * static_cast<std::size_t>(num_actions));
                  });
  return values;
}

}  // namespace ggk::kernels
