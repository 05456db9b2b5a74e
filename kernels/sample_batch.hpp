#pragma once
// A fixed batch of transitions for LSPI, as indices into a feature table.
//
// Sample i is (states[i], actions[i], rewards[i], next_states[i], terminals[i])
// with weight weights[i] (a count after folding duplicates). State ids index the
// table's states: row s * m + a of the feature table is phi(s, a).

#include <cstdint>
#include <vector>

namespace ggk::kernels {

struct SampleBatch {
  std::vector<std::int32_t> states;
  std::vector<std::int32_t> actions;
  std::vector<double> rewards;
  std::vector<std::int32_t> next_states;
  std::vector<std::uint8_t> terminals;  // 1: the episode ended, s' does not bootstrap
  std::vector<double> weights;

  std::size_t size() const { return states.size(); }
  void add(std::int32_t state, std::int32_t action, double reward, std::int32_t next_state,
           bool terminal, double weight = 1.0);
  // Throws std::invalid_argument naming the first inconsistency: column lengths,
  // ids out of [0, num_states) / [0, num_actions), non-finite reward, weight <= 0.
  void validate(std::int32_t num_states, std::int32_t num_actions) const;
};

// Merges identical transitions (same s, a, r, s', terminal) into one sample whose
// weight is the sum of theirs. Samples keep the order of first occurrence, so the
// result is deterministic.
SampleBatch fold_duplicate_samples(const SampleBatch& batch);

}  // namespace ggk::kernels
