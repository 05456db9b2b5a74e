#pragma once
// The Khepera navigation task (paper sec. 4.2): per run, random-walk samples of
// 8-D IR readings -> self-organising map (the graph's nodes) -> graph over units
// from the samples' transitions (weight = prototype distance) -> p random centres
// among the occupied units -> continuous GGK (ED to the best-matching unit plus the
// shortest path from it) or OGK (ED to the centre's prototype) -> copy basis ->
// LSPI -> greedy episodes from the fixed start pose (sum of rewards, stopped by a
// collision).
//
// The samples, SOM, graph and distances of a run are shared by all its fits;
// fits run as oneTBB tasks; streams are keyed by (seed, run, purpose, sweep
// point), so results are identical for any thread count.

#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "engine/job/job_spec.hpp"
#include "engine/job/run_record.hpp"
#include "engine/tasks/khepera/khepera_task_config.hpp"
#include "engine/tasks/task_definition.hpp"

namespace ggk::engine {

// Per-fit metrics, in summary-column order.
// The last four are the graph diagnostics of kernels/graph_diagnostics.hpp
// (engine/tasks/README.md): per run (the same in every fit of a run) the unit
// graph's `edges`, the `median_degree` of its nodes (the occupied units) and the
// `geodesic_stretch` over the pairs of the run's centres (the first
// min(largest kernel count of the job, occupied units) units of the centre
// order: every centre any fit of the run uses), SP over the unit graph and ED
// between the units' prototypes; per fit the `kernel_gap` over every reading of
// the walks and the fit's centres and width, GGK in its continuous form
// ED(s, n(s)) + SP(n(s), c) with n(s) the reading's best-matching unit.
inline const std::vector<std::string>& khepera_metric_names() {
  static const std::vector<std::string> names = {
      "mean_return", "collision_fraction", "mean_steps",       "lspi_iterations", "graph_nodes",
      "edges",       "median_degree",      "geodesic_stretch", "kernel_gap"};
  return names;
}

// The rate among them: collision_fraction; the others are means.
inline MetricKind khepera_metric_kind(std::string_view metric) {
  return metric == "collision_fraction" ? MetricKind::kFraction : MetricKind::kMean;
}

RunRecord run_khepera(const KheperaTaskConfig& config, const JobSpec& job, std::int32_t run,
                      std::span<const SweepPoint> points);

// The peak memory of one run: the walks' readings and samples in their copies,
// the SOM (training and the map), the unit graph and distances, per fit the
// kernel and feature tables over every reading and the LSPI system, and the
// fits' results (episode trajectories).
RunMemoryEstimate estimate_khepera_run(const KheperaTaskConfig& config, const JobSpec& job);

// The Khepera task for the task list: table [khepera], runs through run_khepera().
TaskDefinition khepera_task_definition();

}  // namespace ggk::engine
