#pragma once
// The chain walk (sims/chain) through the discrete protocol: random walks from
// uniformly random states, no goals, and its own test: the fraction of states
// whose greedy action is optimal by value iteration on the exact model.

#include <array>
#include <string_view>
#include <vector>

#include "engine/tasks/discrete_protocol.hpp"
#include "engine/tasks/task_definition.hpp"
#include "sims/chain/chain.hpp"

namespace ggk::engine {

// Its test's metric: optimal_action_fraction (a fraction of the states, tested:
// in the iteration history too); graph_metric_specs() follow it, no goal columns.
std::vector<MetricSpec> chain_policy_metrics();

// The environment view of `chain` (which must outlive it), its metric tested
// against `optimal` (Chain::optimal_actions, also outliving it).
DiscreteEnvironment chain_environment(
    const sims::chain::Chain& chain,
    const std::vector<std::array<bool, sims::chain::kNumActions>>& optimal);

// The chain task for the task list: table [chain].
TaskDefinition chain_task_definition();

}  // namespace ggk::engine
