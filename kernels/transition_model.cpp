#include "kernels/transition_model.hpp"

#include <algorithm>
#include <numeric>
#include <stdexcept>
#include <string>

namespace ggk::kernels {

EmpiricalTransitionModel::EmpiricalTransitionModel(std::int32_t num_states,
                                                   std::int32_t num_actions,
                                                   std::span<const std::int32_t> states,
                                                   std::span<const std::int32_t> actions,
                                                   std::span<const std::int32_t> next_states,
                                                   std::span<const double> weights)
    : num_states_(num_states), num_actions_(num_actions) {
  const std::size_t n = states.size();
  if (actions.size() != n || next_states.size() != n || (!weights.empty() && weights.size() != n)) {
    throw std::invalid_argument("EmpiricalTransitionModel: transition columns differ in length");
  }
  if (num_states < 0 || num_actions <= 0) {
    throw std::invalid_argument("EmpiricalTransitionModel: need num_states >= 0, num_actions > 0");
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (states[i] < 0 || states[i] >= num_states || next_states[i] < 0 ||
        next_states[i] >= num_states || actions[i] < 0 || actions[i] >= num_actions) {
      throw std::invalid_argument("EmpiricalTransitionModel: transition " + std::to_string(i) +
                                  " has an id out of range");
    }
    if (!weights.empty() && !(weights[i] > 0.0)) {
      throw std::invalid_argument("EmpiricalTransitionModel: transition " + std::to_string(i) +
                                  " has a weight <= 0");
    }
  }
  // Sort transitions by (row, successor) and merge equal ones into counts.
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), std::size_t{0});
  auto row_of = [&](std::size_t i) {
    return static_cast<std::int64_t>(states[i]) * num_actions + actions[i];
  };
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    const std::int64_t ra = row_of(a), rb = row_of(b);
    if (ra != rb) return ra < rb;
    if (next_states[a] != next_states[b]) return next_states[a] < next_states[b];
    return a < b;  // fixed summation order of weights
  });
  const auto num_rows = static_cast<std::size_t>(num_states) * num_actions;
  offsets_.assign(num_rows + 1, 0);
  for (std::size_t k = 0; k < n;) {
    const std::size_t i = order[k];
    double count = 0.0;
    std::size_t end = k;
    while (end < n && row_of(order[end]) == row_of(i) &&
           next_states[order[end]] == next_states[i]) {
      count += weights.empty() ? 1.0 : weights[order[end]];
      ++end;
    }
    successors_.push_back(next_states[i]);
    probabilities_.push_back(count);
    ++offsets_[static_cast<std::size_t>(row_of(i)) + 1];
    k = end;
  }
  for (std::size_t r = 1; r <= num_rows; ++r) offsets_[r] += offsets_[r - 1];
  for (std::size_t r = 0; r < num_rows; ++r) {
    const auto begin = static_cast<std::size_t>(offsets_[r]);
    const auto end = static_cast<std::size_t>(offsets_[r + 1]);
    double total = 0.0;
    for (std::size_t e = begin; e < end; ++e) total += probabilities_[e];
    for (std::size_t e = begin; e < end; ++e) probabilities_[e] /= total;
  }
}

}  // namespace ggk::kernels
