#include "sims/chain/chain.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace ggk::sims::chain {

Chain::Chain(ChainConfig config)
    : config_(std::move(config)), is_rewarded_(static_cast<std::size_t>(config_.states), 0) {
  for (const std::int32_t s : config_.rewarded) is_rewarded_[static_cast<std::size_t>(s)] = 1;
}

std::int32_t Chain::move(std::int32_t state, std::int32_t action, bool intended) const {
  const std::int32_t direction = (action == kRight) == intended ? 1 : -1;
  return std::clamp(state + direction, 0, config_.states - 1);
}

double Chain::reward(std::int32_t next_state) const {
  return is_rewarded_[static_cast<std::size_t>(next_state)] ? 1.0 : 0.0;
}

StepResult Chain::step(std::int32_t state, std::int32_t action,
                       kernels::RandomStream& random) const {
  const std::int32_t next = move(state, action, random.uniform() < config_.success);
  return {next, reward(next)};
}

std::vector<std::array<bool, kNumActions>> Chain::optimal_actions(double gamma) const {
  const auto n = static_cast<std::size_t>(config_.states);
  std::vector<double> value(n, 0.0), next_value(n);
  std::vector<std::array<double, kNumActions>> q(n);
  auto backup = [&](std::int32_t s, std::int32_t a) {
    const std::int32_t to = move(s, a, true), away = move(s, a, false);
    return config_.success * (reward(to) + gamma * value[static_cast<std::size_t>(to)]) +
           (1.0 - config_.success) * (reward(away) + gamma * value[static_cast<std::size_t>(away)]);
  };
  for (double change = 1.0; change > 1e-13;) {
    change = 0.0;
    for (std::int32_t s = 0; s < config_.states; ++s) {
      auto& row = q[static_cast<std::size_t>(s)];
      for (std::int32_t a = 0; a < kNumActions; ++a)
        row[static_cast<std::size_t>(a)] = backup(s, a);
      next_value[static_cast<std::size_t>(s)] = std::max(row[0], row[1]);
      change = std::max(change, std::abs(next_value[static_cast<std::size_t>(s)] -
                                         value[static_cast<std::size_t>(s)]));
    }
    std::swap(value, next_value);
  }
  std::vector<std::array<bool, kNumActions>> optimal(n);
  for (std::size_t s = 0; s < n; ++s) {
    const double best = std::max(q[s][0], q[s][1]);
    for (std::size_t a = 0; a < kNumActions; ++a) optimal[s][a] = q[s][a] >= best - 1e-9;
  }
  return optimal;
}

}  // namespace ggk::sims::chain
