#include "kernels/state_action_basis.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>
#include <vector>

namespace ggk::kernels {

namespace {

void check_actions(std::int32_t num_actions) {
  if (num_actions <= 0) {
    throw std::invalid_argument("state-action basis: num_actions must be > 0, got " +
                                std::to_string(num_actions));
  }
}

}  // namespace

SparseRowMatrix copy_basis(const SparseRowMatrix& state_kernels, std::int32_t num_actions) {
  check_actions(num_actions);
  const auto num_states = static_cast<std::int32_t>(state_kernels.rows());
  const auto p = static_cast<std::int32_t>(state_kernels.cols());
  SparseRowMatrix table(static_cast<Eigen::Index>(num_states) * num_actions,
                        static_cast<Eigen::Index>(p) * num_actions);
  table.reserve(state_kernels.nonZeros() * num_actions);
  for (std::int32_t s = 0; s < num_states; ++s) {
    for (std::int32_t a = 0; a < num_actions; ++a) {
      const Eigen::Index row = static_cast<Eigen::Index>(s) * num_actions + a;
      table.startVec(row);
      for (SparseRowMatrix::InnerIterator it(state_kernels, s); it; ++it) {
        table.insertBack(row, static_cast<Eigen::Index>(a) * p + it.col()) = it.value();
      }
    }
  }
  table.finalize();
  return table;
}

SparseRowMatrix shift_basis(const SparseRowMatrix& state_kernels, std::int32_t num_actions,
                            const EmpiricalTransitionModel& model) {
  check_actions(num_actions);
  const auto num_states = static_cast<std::int32_t>(state_kernels.rows());
  const auto p = static_cast<std::int32_t>(state_kernels.cols());
  if (model.num_states() != num_states || model.num_actions() != num_actions) {
    throw std::invalid_argument("shift_basis: the transition model has " +
                                std::to_string(model.num_states()) + " states and " +
                                std::to_string(model.num_actions()) + " actions, the kernels " +
                                std::to_string(num_states) + " states and the basis " +
                                std::to_string(num_actions) + " actions");
  }
  SparseRowMatrix table(static_cast<Eigen::Index>(num_states) * num_actions,
                        static_cast<Eigen::Index>(p) * num_actions);
  table.reserve(state_kernels.nonZeros() * num_actions);
  // Dense accumulator over the p centres; `touched` lists its non-zero slots so a
  // row costs O(non-zeros), not O(p).
  std::vector<double> accumulator(static_cast<std::size_t>(p), 0.0);
  std::vector<char> is_touched(static_cast<std::size_t>(p), 0);
  std::vector<std::int32_t> touched;
  for (std::int32_t s = 0; s < num_states; ++s) {
    for (std::int32_t a = 0; a < num_actions; ++a) {
      const Eigen::Index row = static_cast<Eigen::Index>(s) * num_actions + a;
      table.startVec(row);
      if (!model.observed(s, a)) {  // fall back to copy
        for (SparseRowMatrix::InnerIterator it(state_kernels, s); it; ++it) {
          table.insertBack(row, static_cast<Eigen::Index>(a) * p + it.col()) = it.value();
        }
        continue;
      }
      // Eq. (9): sum_s' P(s'|s,a) K(s', c_j).
      const auto successors = model.successors(s, a);
      const auto probabilities = model.probabilities(s, a);
      if (successors.size() == 1) {
        // One successor (a deterministic task): its row, in column order, each
        // entry the accumulator's 0 + P * K (the same sum without the bookkeeping).
        const double probability = probabilities[0];
        for (SparseRowMatrix::InnerIterator it(state_kernels, successors[0]); it; ++it) {
          table.insertBack(row, static_cast<Eigen::Index>(a) * p + it.col()) =
              0.0 + probability * it.value();
        }
        continue;
      }
      for (std::size_t e = 0; e < successors.size(); ++e) {
        for (SparseRowMatrix::InnerIterator it(state_kernels, successors[e]); it; ++it) {
          const auto j = static_cast<std::size_t>(it.col());
          if (!is_touched[j]) {
            is_touched[j] = 1;
            touched.push_back(static_cast<std::int32_t>(j));
          }
          accumulator[j] += probabilities[e] * it.value();
        }
      }
      std::sort(touched.begin(), touched.end());
      for (std::int32_t j : touched) {
        table.insertBack(row, static_cast<Eigen::Index>(a) * p + j) = accumulator[j];
        accumulator[j] = 0.0;
        is_touched[j] = 0;
      }
      touched.clear();
    }
  }
  table.finalize();
  return table;
}

}  // namespace ggk::kernels
