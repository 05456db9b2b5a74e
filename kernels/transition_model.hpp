#pragma once
// Empirical transition model P(s' | s, a) estimated from observed transitions,
// used by the shift basis of Eq. (9).
//
// Rows are (s, a) pairs in the order s * num_actions + a; each row lists the
// observed successors (sorted by id) with their relative frequencies (weighted
// counts when weights are given). Thread-safety: immutable after construction.

#include <cstdint>
#include <span>
#include <vector>

namespace ggk::kernels {

class EmpiricalTransitionModel {
 public:
  // states/actions/next_states index observed transitions; weights (optional,
  // same length, > 0) count each one. Throws std::invalid_argument on mismatched
  // lengths or out-of-range ids.
  EmpiricalTransitionModel(std::int32_t num_states, std::int32_t num_actions,
                           std::span<const std::int32_t> states,
                           std::span<const std::int32_t> actions,
                           std::span<const std::int32_t> next_states,
                           std::span<const double> weights = {});

  std::int32_t num_states() const { return num_states_; }
  std::int32_t num_actions() const { return num_actions_; }
  bool observed(std::int32_t state, std::int32_t action) const {
    return row_begin(state, action) != row_end(state, action);
  }
  std::span<const std::int32_t> successors(std::int32_t state, std::int32_t action) const {
    return {successors_.data() + row_begin(state, action),
            successors_.data() + row_end(state, action)};
  }
  std::span<const double> probabilities(std::int32_t state, std::int32_t action) const {
    return {probabilities_.data() + row_begin(state, action),
            probabilities_.data() + row_end(state, action)};
  }

 private:
  std::int64_t row_begin(std::int32_t s, std::int32_t a) const {
    return offsets_[static_cast<std::size_t>(s) * num_actions_ + a];
  }
  std::int64_t row_end(std::int32_t s, std::int32_t a) const {
    return offsets_[static_cast<std::size_t>(s) * num_actions_ + a + 1];
  }

  std::int32_t num_states_;
  std::int32_t num_actions_;
  std::vector<std::int64_t> offsets_;
  std::vector<std::int32_t> successors_;
  std::vector<double> probabilities_;
};

}  // namespace ggk::kernels
