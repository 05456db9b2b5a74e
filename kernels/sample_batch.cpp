#include "kernels/sample_batch.hpp"

#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>
#include <unordered_map>

namespace ggk::kernels {

void SampleBatch::add(std::int32_t state, std::int32_t action, double reward,
                      std::int32_t next_state, bool terminal, double weight) {
  states.push_back(state);
  actions.push_back(action);
  rewards.push_back(reward);
  next_states.push_back(next_state);
  terminals.push_back(terminal ? 1 : 0);
  weights.push_back(weight);
}

void SampleBatch::validate(std::int32_t num_states, std::int32_t num_actions) const {
  const std::size_t n = states.size();
  if (actions.size() != n || rewards.size() != n || next_states.size() != n ||
      terminals.size() != n || weights.size() != n) {
    throw std::invalid_argument(
        "sample batch: columns differ in length (states " + std::to_string(n) + ", actions " +
        std::to_string(actions.size()) + ", rewards " + std::to_string(rewards.size()) +
        ", next_states " + std::to_string(next_states.size()) + ", terminals " +
        std::to_string(terminals.size()) + ", weights " + std::to_string(weights.size()) + ")");
  }
  for (std::size_t i = 0; i < n; ++i) {
    const std::string where = "sample batch: sample " + std::to_string(i) + ": ";
    if (states[i] < 0 || states[i] >= num_states || next_states[i] < 0 ||
        next_states[i] >= num_states) {
      throw std::invalid_argument(where + "state id outside [0, " + std::to_string(num_states) +
                                  ")");
    }
    if (actions[i] < 0 || actions[i] >= num_actions) {
      throw std::invalid_argument(where + "action outside [0, " + std::to_string(num_actions) +
                                  ")");
    }
    if (!std::isfinite(rewards[i])) throw std::invalid_argument(where + "non-finite reward");
    if (!(weights[i] > 0.0) || !std::isfinite(weights[i])) {
      throw std::invalid_argument(where + "weight must be finite and > 0");
    }
  }
}

SampleBatch fold_duplicate_samples(const SampleBatch& batch) {
  struct Key {
    std::int32_t state, action, next_state;
    std::uint8_t terminal;
    std::uint64_t reward_bits;  // bitwise equality of rewards
    bool operator==(const Key&) const = default;
  };
  struct KeyHash {
    std::size_t operator()(const Key& k) const {
      std::uint64_t h = 1469598103934665603ull;
      for (std::uint64_t v :
           {std::uint64_t(std::uint32_t(k.state)), std::uint64_t(std::uint32_t(k.action)),
            std::uint64_t(std::uint32_t(k.next_state)), std::uint64_t(k.terminal), k.reward_bits}) {
        h = (h ^ v) * 1099511628211ull;
        h ^= h >> 29;
      }
      return static_cast<std::size_t>(h);
    }
  };
  std::unordered_map<Key, std::size_t, KeyHash> slot_of;
  slot_of.reserve(batch.size());
  SampleBatch folded;
  for (std::size_t i = 0; i < batch.size(); ++i) {
    std::uint64_t bits;
    std::memcpy(&bits, &batch.rewards[i], sizeof bits);
    const Key key{batch.states[i], batch.actions[i], batch.next_states[i], batch.terminals[i],
                  bits};
    const auto [it, inserted] = slot_of.try_emplace(key, folded.size());
    if (inserted) {
      folded.add(batch.states[i], batch.actions[i], batch.rewards[i], batch.next_states[i],
                 batch.terminals[i] != 0, batch.weights[i]);
    } else {
      folded.weights[it->second] += batch.weights[i];
    }
  }
  return folded;
}

}  // namespace ggk::kernels
