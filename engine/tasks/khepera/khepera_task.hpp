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
// point), so results are identical for any thread count. The walks and the
// greedy episodes: khepera_episodes.hpp; the geometry of Fig. 4(a):
// khepera_arena.hpp; the memory estimate: khepera_memory.hpp.

#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "engine/job/job_spec.hpp"
#include "engine/tasks/graph_protocol.hpp"
#include "engine/tasks/khepera/khepera_task_config.hpp"
#include "engine/tasks/run_record.hpp"
#include "engine/tasks/task_definition.hpp"

namespace ggk::engine {

// Per-fit metrics, in summary-column order: the episodes' mean_return,
// collision_fraction (a fraction of the episodes) and mean_steps (all tested:
// in the iteration history too), then graph_metric_specs() (graph_protocol.hpp)
// over the unit graph: its nodes are the occupied units, the stretch's ED is
// between the units' prototypes, and the kernel gap runs over every reading of
// the walks, GGK in its continuous form ED(s, n(s)) + SP(n(s), c) with n(s) the
// reading's best-matching unit.
const std::vector<MetricSpec>& khepera_metric_specs();
const std::vector<std::string>& khepera_metric_names();
MetricKind khepera_metric_kind(std::string_view metric);

RunRecord run_khepera(const KheperaTaskConfig& config, const JobSpec& job, std::int32_t run,
                      std::span<const SweepPoint> points);

// The Khepera task for the task list: table [khepera], runs through run_khepera().
TaskDefinition khepera_task_definition();

}  // namespace ggk::engine
