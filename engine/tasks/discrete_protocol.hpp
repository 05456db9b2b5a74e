#pragma once
// The experiment protocol shared by tasks with a finite state set (maze, arm,
// chain): per run, random-walk samples -> graph over visited states -> kernel
// centres (goals first, then random visited nodes) -> GGK / OGK state kernels ->
// copy or shift basis (Eq. 9) -> LSPI -> the greedy policy's test: the goal test
// (roll-outs from every start state) or the task's own (DiscreteEnvironment::
// test_policy). The run's graph, centres and distances: graph_protocol.hpp.
//
// A run's samples, graph, transition model and shortest-path distances are
// computed once and shared by all its fits (the sweep points), so GGK and OGK are
// compared on the same samples. Fits run as oneTBB tasks; every random number
// comes from streams keyed by (seed, run, purpose, sweep point), so the record is
// identical for any thread count.

#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "engine/job/job_spec.hpp"
#include "engine/job/sweep.hpp"
#include "engine/tasks/graph_protocol.hpp"
#include "engine/tasks/run_memory.hpp"
#include "engine/tasks/run_record.hpp"
#include "kernels/eigen_types.hpp"
#include "kernels/random_stream.hpp"

namespace ggk::engine {

struct Transition {
  std::int32_t next_state = 0;
  double reward = 0.0;
  bool terminal = false;
};

// A finite environment as the protocol sees it. step and test_policy must be
// thread-safe (they are called from parallel tasks; step with distinct streams).
struct DiscreteEnvironment {
  std::int32_t num_states = 0;
  std::int32_t num_actions = 0;
  std::vector<std::string> action_names;  // of codes 0 .. num_actions - 1 (the results file's)
  kernels::RowMatrixXd state_vectors;     // num_states x d, for Euclidean distances
  std::vector<std::int32_t> goal_states;  // sorted; none for a task without goals
  // The random walks' series start here, and the goal test's roll-outs (the
  // non-goal states of a task with goals; every state of one without).
  std::vector<std::int32_t> start_states;
  // Start states with a name (the arm's "A"): each adds the metrics
  // success_from_<name>, steps_from_<name> and the array trajectory_<name>.
  std::vector<std::pair<std::string, std::int32_t>> named_starts;
  std::function<Transition(std::int32_t state, std::int32_t action, kernels::RandomStream&)> step;
  // The test of a greedy policy (one action per state). Unset: the goal test
  // (the metrics success_rate and mean_steps_to_goal, the array steps_to_goal,
  // the named starts'). Set: the task's own test, which sets the metrics
  // declared in policy_metrics (all tested: in the iteration history too) and
  // adds no goal columns.
  std::vector<MetricSpec> policy_metrics;
  std::function<void(const std::vector<std::int32_t>& policy, FitMetrics& metrics)> test_policy;
};

struct DiscreteProtocol {
  std::int32_t series = 1;            // random-walk series per run
  std::int32_t steps_per_series = 1;  // uniformly random actions per series
  std::int32_t test_max_steps = 100;  // greedy steps allowed to reach a goal
  // false: a series restarts from a random start after entering a goal (maze).
  // true: the walk goes on from the goal (its moves are sampled as terminal,
  // reward-0 transitions), so every goal joins the graph and can be a centre, as
  // the arm protocol of the paper needs (all 16 goals are centres).
  bool walk_through_goals = false;
};

// The per-fit metrics of `env` in summary-column order: its test's
// (success_rate and mean_steps_to_goal for the goal test, else
// env.policy_metrics), graph_metric_specs() (graph_protocol.hpp; the graph's
// nodes are the visited states, the kernel gap's states the visited states),
// then success_from_<name> and steps_from_<name> of each named start.
std::vector<MetricSpec> discrete_metric_specs(const DiscreteEnvironment& env,
                                              const DiscreteProtocol& protocol);
// The same from what decides them, for a task that knows them without building
// its environment: env.policy_metrics (empty: the goal test's) and the names of
// env.named_starts.
std::vector<MetricSpec> discrete_metric_specs(std::span<const MetricSpec> policy_metrics,
                                              std::span<const std::string> named_starts,
                                              const DiscreteProtocol& protocol);

// The names of discrete_metric_specs() for a goal task without named starts.
const std::vector<std::string>& discrete_metric_names();

// A discrete task's TaskDefinition::datasets: `own` (the task's declarations),
// then the discrete protocol's (start_states, graph/visited, a fit's
// state_values, steps_to_goal and trajectories), then graph_dataset_specs().
std::vector<DatasetSpecs> discrete_dataset_specs(std::span<const DatasetSpecs> own = {});

// What a run's memory depends on, known before the environment is built.
struct DiscreteSizes {
  double states = 0.0;
  double state_dimension = 2.0;
  double actions = 4.0;
  // Distinct successors of a state and action (for the folded batch): 1 for a
  // deterministic environment.
  double successors = 1.0;
  double named_starts = 0.0;     // each adds a stored trajectory per fit
  double simulator_bytes = 0.0;  // what the simulator itself holds (map, joint grid)
  std::string states_are;        // how the message names the states: "free cells"
};

// The peak memory of one run of the protocol (run_memory.hpp), from the job's
// sizes alone: the samples in their copies (the raw walk, the record, the
// episodic and the folded batch), the sample graph, the geodesic distances from
// the most centres any sweep point uses, per fit the kernel and feature tables
// and the LSPI system of the largest kernel count, and the fits' results.
RunMemoryEstimate estimate_discrete_run(const DiscreteSizes& sizes,
                                        const DiscreteProtocol& protocol, const JobSpec& job);

// Runs one run of the protocol for every sweep point. Throws only on programmer
// errors; a fit that cannot start (more kernels than graph nodes) or whose LSPI
// system fails is recorded with its status and message.
RunRecord run_discrete_protocol(const DiscreteEnvironment& environment,
                                const DiscreteProtocol& protocol, const JobSpec& job,
                                std::int32_t run, std::span<const SweepPoint> points);

}  // namespace ggk::engine
