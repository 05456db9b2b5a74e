#include "engine/tasks/chain/chain_task.hpp"

#include "engine/tasks/chain/chain_table.hpp"

#include <array>

namespace ggk::engine {

namespace chain = sims::chain;
using OptimalActions = std::vector<std::array<bool, chain::kNumActions>>;

std::vector<MetricSpec> chain_policy_metrics() {
  return {tested(fraction_metric("optimal_action_fraction",
                                 "share of the states whose greedy action is optimal (value "
                                 "iteration on the exact model)"))};
}

DiscreteEnvironment chain_environment(const chain::Chain& chain, const OptimalActions& optimal) {
  DiscreteEnvironment env;
  env.num_states = chain.num_states();
  env.num_actions = chain::kNumActions;
  env.action_names = {"left", "right"};             // chain::kLeft, chain::kRight
  env.state_vectors.resize(chain.num_states(), 1);  // positions 1 .. n, the paper's numbering
  for (std::int32_t s = 0; s < chain.num_states(); ++s) env.state_vectors(s, 0) = s + 1.0;
  for (std::int32_t s = 0; s < chain.num_states(); ++s) env.start_states.push_back(s);
  env.step = [&chain](std::int32_t state, std::int32_t action, kernels::RandomStream& random) {
    const chain::StepResult r = chain.step(state, action, random);
    return Transition{r.next_state, r.reward, false};
  };
  env.policy_metrics = chain_policy_metrics();
  env.test_policy = [&optimal](const std::vector<std::int32_t>& policy, FitMetrics& metrics) {
    double optimal_states = 0.0;
    for (std::size_t s = 0; s < optimal.size(); ++s) {
      optimal_states += optimal[s][static_cast<std::size_t>(policy[s])] ? 1.0 : 0.0;
    }
    metrics.set("optimal_action_fraction", optimal_states / static_cast<double>(optimal.size()));
  };
  return env;
}

namespace {

DiscreteProtocol chain_protocol(const chain::ChainConfig& config) {
  return {config.series, config.steps_per_series};
}

RunRecord run_chain(const JobSpec& job, std::int32_t run, std::span<const SweepPoint> points) {
  const chain::Chain chain(task_config_as<chain::ChainConfig>(job));
  const OptimalActions optimal = chain.optimal_actions(job.lspi.gamma);
  RunRecord record = run_discrete_protocol(chain_environment(chain, optimal),
                                           chain_protocol(chain.config()), job, run, points);
  NamedArray table{
      "optimal_actions", {chain.num_states(), chain::kNumActions}, {}, ElementType::kInt32};
  for (const auto& actions : optimal)
    table.values.insert(table.values.end(), {actions[0] * 1.0, actions[1] * 1.0});
  record.arrays.push_back(std::move(table));
  return record;
}

RunMemoryEstimate estimate_chain_run(const JobSpec& job) {
  const auto& config = task_config_as<chain::ChainConfig>(job);
  DiscreteSizes sizes;
  sizes.states = config.states;
  sizes.state_dimension = 1.0;
  sizes.actions = chain::kNumActions;
  sizes.successors = 2.0;
  sizes.simulator_bytes = 17.0 * config.states;  // rewarded flags, optimal actions (+ record)
  sizes.states_are = "states of the chain";
  return estimate_discrete_run(sizes, chain_protocol(config), job);
}

}  // namespace

constexpr std::array kChainDatasets = {
    DatasetSpec{"optimal_actions", "state,action", "flag",
                "chain: 1 where the action is optimal by value iteration"},
};

TaskDefinition chain_task_definition() {
  const DatasetSpecs own[] = {{"chain", kChainDatasets}};
  return {{"chain",
           [](const TomlTableReader& job, const std::filesystem::path&,
              std::vector<JobInput>&) -> std::any { return parse_chain_table(job); }},
          run_chain,
          estimate_chain_run,
          [](const JobSpec& job) {
            return discrete_metric_specs(chain_policy_metrics(), {},
                                         chain_protocol(task_config_as<chain::ChainConfig>(job)));
          },
          discrete_dataset_specs(own)};
}

}  // namespace ggk::engine
