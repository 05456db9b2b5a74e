#pragma once
// Lagoudakis & Parr's chain walk (JMLR 4, 2003, sec. 9.1): states 0 .. n-1 on a
// line (the paper's states 1 .. n), actions left and right that move one state
// the intended way with probability `success` and the other way otherwise; the
// ends are dead ends (a move past one stays there). Reward 1 for entering a
// rewarded state, else 0; no terminal states.
//
// Thread-safety: Chain is immutable; step() may be called from many threads
// with distinct streams.

#include <array>
#include <cstdint>
#include <vector>

#include "kernels/random_stream.hpp"

namespace ggk::sims::chain {

inline constexpr std::int32_t kLeft = 0;
inline constexpr std::int32_t kRight = 1;
inline constexpr std::int32_t kNumActions = 2;

struct ChainConfig {
  std::int32_t states = 20;                      // the paper's 20-state chain (>= 2)
  double success = 0.9;                          // probability that a move goes the intended way
  std::vector<std::int32_t> rewarded = {0, 19};  // 0-based; the paper's states 1 and 20
  std::int32_t series = 100;                     // random-walk series per run
  std::int32_t steps_per_series = 50;            // uniformly random actions per series
};

struct StepResult {
  std::int32_t next_state = 0;
  double reward = 0.0;
};

class Chain {
 public:
  explicit Chain(ChainConfig config);  // config as its table parser checked it

  std::int32_t num_states() const { return config_.states; }
  const ChainConfig& config() const { return config_; }

  // The state `action` leads to when it goes the intended way (moved = true) or
  // the other way.
  std::int32_t move(std::int32_t state, std::int32_t action, bool intended) const;
  double reward(std::int32_t next_state) const;
  StepResult step(std::int32_t state, std::int32_t action, kernels::RandomStream& random) const;

  // Per state, which actions are optimal for discount gamma in [0, 1): value
  // iteration on the exact model until no value changes by more than 1e-13
  // (then every Q* is within 1e-11 of its limit), and an action is optimal when
  // its Q* is within 1e-9 of the state's best, so that ties (equal Q* up to
  // rounding) make both actions optimal.
  std::vector<std::array<bool, kNumActions>> optimal_actions(double gamma) const;

 private:
  ChainConfig config_;
  std::vector<std::uint8_t> is_rewarded_;
};

}  // namespace ggk::sims::chain
