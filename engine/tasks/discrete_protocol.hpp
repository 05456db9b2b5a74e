#pragma once
// The experiment protocol shared by tasks with a finite state set (maze, arm):
// per run, random-walk samples -> graph over visited states -> kernel centres
// (goals first, then random visited nodes) -> GGK / OGK state kernels -> copy or
// shift basis (Eq. 9) -> LSPI -> greedy policy tested from every start state.
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
#include "engine/job/run_record.hpp"
#include "engine/job/sweep.hpp"
#include "engine/tasks/run_memory.hpp"
#include "kernels/eigen_types.hpp"
#include "kernels/random_stream.hpp"

namespace ggk::engine {

struct Transition {
  std::int32_t next_state = 0;
  double reward = 0.0;
  bool terminal = false;
};

// A finite environment as the protocol sees it. step must be thread-safe for
// distinct streams (it is called from parallel tasks).
struct DiscreteEnvironment {
  std::int32_t num_states = 0;
  std::int32_t num_actions = 0;
  kernels::RowMatrixXd state_vectors;      // num_states x d, for Euclidean distances
  std::vector<std::int32_t> goal_states;   // sorted
  std::vector<std::int32_t> start_states;  // series and tests start here (non-goal states)
  // Start states with a name (the arm's "A"): each adds the metrics
  // success_from_<name>, steps_from_<name> and the array trajectory_<name>.
  std::vector<std::pair<std::string, std::int32_t>> named_starts;
  std::function<Transition(std::int32_t state, std::int32_t action, kernels::RandomStream&)> step;
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

// Per-fit metrics of this protocol, in summary-column order; the metrics of the
// named starts follow them. The last four are the graph diagnostics of
// kernels/graph_diagnostics.hpp (engine/tasks/README.md): per run (the same in
// every fit of a run) the sample graph's `edges`, the `median_degree` of its
// nodes (the visited states) and the `geodesic_stretch` over the pairs of the
// run's centres (the first min(largest kernel count of the job, nodes) entries
// of the centre order: every centre any fit of the run uses); per fit the
// `kernel_gap` over the visited states and the fit's centres and width.
inline const std::vector<std::string>& discrete_metric_names() {
  static const std::vector<std::string> names = {
      "success_rate", "mean_steps_to_goal", "lspi_iterations",  "graph_nodes",
      "edges",        "median_degree",      "geodesic_stretch", "kernel_gap"};
  return names;
}

// success_rate is a fraction (of the start states, per run); success_from_<name>
// of each named start a rate (0 or 1 per fit); the others are means.
inline MetricKind discrete_metric_kind(std::string_view metric) {
  return metric == "success_rate"              ? MetricKind::kFraction
         : metric.starts_with("success_from_") ? MetricKind::kRate
                                               : MetricKind::kMean;
}

// For every state (row of state_vectors), the nearest visited state (itself when
// visited) and the Euclidean distance to it, (row(s) - row(v)).norm(); ties go
// to the lowest state id, exactly as a scan over the visited states in id order.
// With no visited state, every unvisited state gets state 0 at infinite distance.
// GGK values of unvisited states follow the continuous form
// SP(s, c) = ED(s, n(s)) + SP(n(s), c). A k-d tree: O(n log n) on grids (a scan
// over the visited states would be O(n^2)). Queries run as oneTBB tasks.
void nearest_visited_states(const kernels::RowMatrixXd& state_vectors,
                            const std::vector<std::uint8_t>& visited,
                            std::vector<std::int32_t>& nearest, std::vector<double>& distance);

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
