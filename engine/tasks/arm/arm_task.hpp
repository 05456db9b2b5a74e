#pragma once
// The robot-arm task (paper sec. 4.1): the two-joint arm (sims/arm) on its joint
// grid, run through the discrete protocol with the named start A (Figs. 1-3).

#include <cstdint>
#include <span>
#include <vector>

#include "engine/job/job_spec.hpp"
#include "engine/tasks/discrete_protocol.hpp"
#include "engine/tasks/run_record.hpp"
#include "engine/tasks/task_definition.hpp"
#include "sims/arm/arm.hpp"

namespace ggk::engine {

// The environment view of an arm; `arm` must outlive it. Series and tests start
// from every free non-goal pose; A is a named start.
DiscreteEnvironment arm_environment(const sims::arm::Arm& arm);

// One run; besides the protocol's record it stores the joint grid (grid/state_of:
// state id per cell or -1 for a colliding pose; grid/goal: 1 on goal cells) for
// the figures.
RunRecord run_arm(const sims::arm::ArmConfig& config, const JobSpec& job, std::int32_t run,
                  std::span<const SweepPoint> points);

// The workspace for Fig. 1(a) (results/plot_arm_workspace.py), stored with every
// run: workspace/rectangles [n, 4] (min x, min y, max x, max y),
// workspace/discs [n, 3] (centre, radius), workspace/object [3] (centre,
// radius), workspace/pose_A [3, 2] (base, elbow, end effector at A),
// workspace/pose_A_deg [2], workspace/goal_poses [goals, 6] (base, elbow, end
// effector, x then y each) and workspace/goal_poses_deg [goals, 2] (shoulder,
// elbow), goals in id order. (The store keeps 1-D and 2-D arrays.)
std::vector<NamedArray> workspace_arrays(const sims::arm::Arm& arm,
                                         const sims::arm::ArmConfig& config);

// The peak memory of one run (estimate_discrete_run with the arm's free poses,
// plus the joint grid stored with the run).
RunMemoryEstimate estimate_arm_run(const sims::arm::ArmConfig& config, const JobSpec& job);

// The arm task for the task list: table [arm], runs through run_arm().
TaskDefinition arm_task_definition();

}  // namespace ggk::engine
