#include "engine/tasks/arm/arm_task.hpp"

#include "engine/tasks/arm/arm_table.hpp"

#include <array>
#include <utility>
#include <variant>
#include <vector>

#include "sims/arm/kinematics.hpp"

namespace ggk::engine {

namespace {
// The paper's start A (Fig. 1(a)): the metrics success_from_A, steps_from_A.
const std::string kArmStartName = "A";

DiscreteProtocol arm_protocol(const sims::arm::ArmConfig& config) {
  // The walk goes on through goals so that all 16 goals join the graph and become
  // the first centres, as in the paper (a restart at each goal leaves ~9 of them
  // unvisited: the inner goal cells are only reachable through other goals).
  return {config.series, config.steps_per_series, config.test_max_steps,
          /*walk_through_goals=*/true};
}
}  // namespace

DiscreteEnvironment arm_environment(const sims::arm::Arm& arm) {
  DiscreteEnvironment env;
  env.num_states = arm.num_states();
  env.num_actions = arm.num_actions();
  for (std::int32_t a = 0; a < env.num_actions; ++a) {
    env.action_names.emplace_back(sims::arm::action_name(a));
  }
  env.state_vectors = arm.state_vectors();
  env.goal_states = arm.goal_states();
  for (std::int32_t s = 0; s < arm.num_states(); ++s) {
    if (!arm.is_goal(s)) env.start_states.push_back(s);
  }
  env.named_starts = {{kArmStartName, arm.start_state_A()}};
  env.step = [&arm](std::int32_t state, std::int32_t action, kernels::RandomStream&) {
    const sims::arm::StepResult r = arm.step(state, action);
    return Transition{r.next_state, r.reward, r.terminal};
  };
  return env;
}

namespace {

// The pose's base, elbow and end effector, x then y each.
void push_pose(std::vector<double>& values, const sims::arm::ArmGeometry& geometry,
               double shoulder_deg, double elbow_deg) {
  const sims::arm::ArmPose pose = sims::arm::forward_kinematics(geometry, shoulder_deg, elbow_deg);
  values.insert(values.end(), {pose.base.x, pose.base.y, pose.elbow.x, pose.elbow.y,
                               pose.end_effector.x, pose.end_effector.y});
}

}  // namespace

std::vector<NamedArray> workspace_arrays(const sims::arm::Arm& arm,
                                         const sims::arm::ArmConfig& config) {
  const sims::arm::ArmGeometry& g = config.geometry;
  NamedArray rectangles{"workspace/rectangles", {0, 4}, {}}, discs{"workspace/discs", {0, 3}, {}};
  for (const sims::arm::Obstacle& obstacle : g.obstacles) {
    if (const auto* r = std::get_if<sims::arm::Rectangle>(&obstacle)) {
      rectangles.values.insert(rectangles.values.end(), {r->min.x, r->min.y, r->max.x, r->max.y});
    } else if (const auto* d = std::get_if<sims::arm::Disc>(&obstacle)) {
      discs.values.insert(discs.values.end(), {d->center.x, d->center.y, d->radius});
    }
  }
  rectangles.shape[0] = static_cast<std::int64_t>(rectangles.values.size() / 4);
  discs.shape[0] = static_cast<std::int64_t>(discs.values.size() / 3);
  NamedArray object{
      "workspace/object", {3}, {g.object.center.x, g.object.center.y, g.object.radius}};
  NamedArray pose_a{"workspace/pose_A", {3, 2}, {}};
  push_pose(pose_a.values, g, config.start_A.shoulder_deg, config.start_A.elbow_deg);
  NamedArray angles_a{
      "workspace/pose_A_deg", {2}, {config.start_A.shoulder_deg, config.start_A.elbow_deg}};
  NamedArray goals{"workspace/goal_poses", {0, 6}, {}};
  NamedArray goal_angles{"workspace/goal_poses_deg", {0, 2}, {}};
  for (std::int32_t s : arm.goal_states()) {
    const sims::arm::JointAngles angles = arm.angles_of(s);
    push_pose(goals.values, g, angles.shoulder_deg, angles.elbow_deg);
    goal_angles.values.insert(goal_angles.values.end(), {angles.shoulder_deg, angles.elbow_deg});
  }
  goals.shape[0] = static_cast<std::int64_t>(arm.goal_states().size());
  goal_angles.shape[0] = goals.shape[0];
  return {std::move(rectangles), std::move(discs), std::move(object),     std::move(pose_a),
          std::move(angles_a),   std::move(goals), std::move(goal_angles)};
}

RunRecord run_arm(const sims::arm::ArmConfig& config, const JobSpec& job, std::int32_t run,
                  std::span<const SweepPoint> points) {
  const sims::arm::Arm arm(config);
  const DiscreteEnvironment env = arm_environment(arm);
  RunRecord record = run_discrete_protocol(env, arm_protocol(config), job, run, points);

  const std::int64_t rows = arm.shoulder_steps(), cols = arm.elbow_steps();
  NamedArray state_of{"grid/state_of", {rows, cols}, {}, ElementType::kInt32};
  NamedArray goal{"grid/goal", {rows, cols}, {}, ElementType::kInt32};
  for (std::int32_t i = 0; i < rows; ++i) {
    for (std::int32_t j = 0; j < cols; ++j) {
      const std::int32_t s = arm.state_of(i, j);
      state_of.values.push_back(s);
      goal.values.push_back(s != sims::arm::kNoState && arm.is_goal(s) ? 1.0 : 0.0);
    }
  }
  record.arrays.push_back(std::move(state_of));
  record.arrays.push_back(std::move(goal));
  for (NamedArray& array : workspace_arrays(arm, config)) record.arrays.push_back(std::move(array));
  return record;
}

RunMemoryEstimate estimate_arm_run(const sims::arm::ArmConfig& config, const JobSpec& job) {
  const sims::arm::Arm arm(config);  // as the parser built it (3600 x 3600 poses at most)
  const double cells = static_cast<double>(arm.shoulder_steps()) * arm.elbow_steps();
  DiscreteSizes sizes;
  sizes.states = arm.num_states();
  sizes.actions = arm.num_actions();
  sizes.named_starts = 1.0;  // A
  // The grid of state ids and per state its cell and goal flag.
  sizes.simulator_bytes = 4.0 * cells + 9.0 * arm.num_states();
  sizes.states_are = "free poses of the arm";
  RunMemoryEstimate estimate = estimate_discrete_run(sizes, arm_protocol(config), job);
  // grid/state_of and grid/goal in the record (doubles, grown by doubling).
  const double grid = 2.0 * 2.0 * 8.0 * cells;
  // The workspace arrays for Fig. 1(a): obstacles, object, pose A, the goals'
  // poses (6 + 2 doubles each).
  const double workspace = (static_cast<double>(config.geometry.obstacles.size()) * 4.0 + 17.0 +
                            static_cast<double>(arm.goal_states().size()) * 8.0) *
                           8.0;
  estimate.add("the joint grid (" + count_text(cells) + " poses)", grid);
  estimate.record_bytes += grid + workspace;
  return estimate;
}

// The arm's own arrays: its joint grid and its workspace's geometry.
constexpr std::array kArmDatasets = {
    DatasetSpec{"grid/state_of", "shoulder,elbow", "node id",
                "arm: the state of each joint-grid cell, -1 = collision"},
    DatasetSpec{"grid/goal", "shoulder,elbow", "flag", "arm: 1 where the cell is a goal state"},
    DatasetSpec{"workspace/rectangles", "rectangle,corner_xy", "workspace units",
                "arm obstacles: min x, min y, max x, max y"},
    DatasetSpec{"workspace/discs", "disc,disc_field", "workspace units",
                "arm obstacles: centre x, y, radius"},
    DatasetSpec{"workspace/object", "disc_field", "workspace units",
                "arm: the object, centre x, y, radius"},
    DatasetSpec{"workspace/pose_A", "joint_point,xy", "workspace units",
                "arm: base, elbow and hand of pose A"},
    DatasetSpec{"workspace/pose_A_deg", "joint", "degrees", "arm: shoulder and elbow angle of A"},
    DatasetSpec{"workspace/goal_poses", "goal,pose_xy", "workspace units",
                "arm: base, elbow and hand (x, y each) of each goal pose"},
    DatasetSpec{"workspace/goal_poses_deg", "goal,joint", "degrees",
                "arm: shoulder and elbow angle of each goal pose"},
};

TaskDefinition arm_task_definition() {
  const DatasetSpecs own[] = {{"arm", kArmDatasets}};
  return {{"arm",
           [](const TomlTableReader& job, const std::filesystem::path&,
              std::vector<JobInput>&) -> std::any { return parse_arm_table(job); }},
          [](const JobSpec& job, std::int32_t run, std::span<const SweepPoint> points) {
            return run_arm(task_config_as<sims::arm::ArmConfig>(job), job, run, points);
          },
          [](const JobSpec& job) {
            return estimate_arm_run(task_config_as<sims::arm::ArmConfig>(job), job);
          },
          [](const JobSpec& job) {
            const std::string named_starts[] = {kArmStartName};
            return discrete_metric_specs({}, named_starts,
                                         arm_protocol(task_config_as<sims::arm::ArmConfig>(job)));
          },
          discrete_dataset_specs(own)};
}

}  // namespace ggk::engine
