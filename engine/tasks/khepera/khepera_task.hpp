#pragma once
// The Khepera navigation task (paper sec. 4.2) on the continuous protocol
// (engine/tasks/continuous_protocol.hpp): per run, random-walk samples of 8-D IR
// readings (unscaled) -> self-organising map (the graph's nodes) -> graph over
// units -> continuous GGK, OGK or PVF -> copy basis -> LSPI -> greedy episodes
// from the fixed start pose (sum of rewards, stopped by a collision). This task
// supplies the robot (a pose behind ContinuousEpisode), its actions, its
// collision flags (samples/collisions) and the geometry of Fig. 4(a)
// (khepera_arena.hpp).

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
std::vector<MetricSpec> khepera_metric_specs(const KheperaTaskConfig& config);
const std::vector<std::string>& khepera_metric_names();  // the same for any job

// The walks' readings and samples in their copies, the SOM, the unit graph and
// distances, per fit the kernel table over every reading and the LSPI system,
// and the fits' results (episode trajectories): estimate_continuous_run with the
// robot's sizes and its arena's arrays.
RunMemoryEstimate estimate_khepera_run(const KheperaTaskConfig& config, const JobSpec& job);

RunRecord run_khepera(const KheperaTaskConfig& config, const JobSpec& job, std::int32_t run,
                      std::span<const SweepPoint> points);

// The Khepera task for the task list: table [khepera], runs through run_khepera().
TaskDefinition khepera_task_definition();

}  // namespace ggk::engine
