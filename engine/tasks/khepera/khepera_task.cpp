#include "engine/tasks/khepera/khepera_task.hpp"

#include <algorithm>
#include <array>
#include <memory>
#include <string>

#include "engine/tasks/continuous_protocol.hpp"
#include "engine/tasks/khepera/khepera_arena.hpp"
#include "engine/tasks/khepera/khepera_table.hpp"
#include "sims/khepera/khepera.hpp"

namespace ggk::engine {

namespace {

namespace khepera = sims::khepera;

// The robot behind the continuous protocol: the hidden state is the pose; a
// walk starts from a random free pose, a test from the arena's start pose; a
// collision (the move undone) stops a test episode but not a walk.
class KheperaEpisode final : public ContinuousEpisode {
 public:
  explicit KheperaEpisode(const khepera::Khepera& robot) : robot_(robot) {}

  void start_walk(kernels::RandomStream& random, std::span<double> observation) override {
    pose_ = robot_.sample_free_pose(random);
    copy(robot_.sense(pose_, random), observation);
  }
  void start_test(kernels::RandomStream& random, std::span<double> observation) override {
    pose_ = robot_.start_pose();
    copy(robot_.sense(pose_, random), observation);
  }
  ContinuousStep step(std::int32_t action, kernels::RandomStream& random,
                      std::span<double> observation) override {
    const khepera::StepResult r = robot_.step(pose_, action, random);
    pose_ = r.next_pose;
    copy(r.observation, observation);
    return {r.reward, false, false, r.collided};
  }
  void trace(std::vector<double>& out) const override {
    out.insert(out.end(), {pose_.x, pose_.y, pose_.heading});
  }

 private:
  static void copy(const khepera::Readings& readings, std::span<double> observation) {
    std::copy(readings.begin(), readings.end(), observation.begin());
  }

  const khepera::Khepera& robot_;
  khepera::Pose pose_;
};

ContinuousEnvironment khepera_environment(const khepera::Khepera& robot) {
  ContinuousEnvironment env;
  env.observation_dimension = khepera::kNumSensors;
  env.num_actions = khepera::kNumActions;
  for (std::int32_t a = 0; a < khepera::kNumActions; ++a) {
    env.action_names.emplace_back(khepera::action_name(a));
  }
  env.new_episode = [&robot] { return std::make_unique<KheperaEpisode>(robot); };
  env.trace_dimension = 3;  // x, y, heading
  env.ended_metric = "collision_fraction";
  const khepera::Rewards rewards = robot.config().rewards;  // 0: a turn or a backward step
  env.reward_low = std::min({0.0, rewards.forward, rewards.collision});
  env.reward_high = std::max({0.0, rewards.forward, rewards.collision});
  // A collision stops the episode: at most one, after at most steps - 1 others.
  env.return_range = [rewards](std::int32_t steps) {
    const double others = std::max(steps - 1, 0);
    return std::pair{std::min(0.0, rewards.collision) + others * std::min(0.0, rewards.forward),
                     others * std::max(0.0, rewards.forward) +
                         std::max({0.0, rewards.forward, rewards.collision})};
  };
  env.stop_flags_array = "samples/collisions";
  env.run_arrays = arena_arrays(robot);
  env.store_scale = false;  // raw readings (khepera_task_config.hpp)
  return env;
}

}  // namespace

std::vector<MetricSpec> khepera_metric_specs(const KheperaTaskConfig& config) {
  const khepera::Khepera robot(config.simulator);
  return continuous_metric_specs(khepera_environment(robot), config.protocol);
}

const std::vector<std::string>& khepera_metric_names() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> result;
    ContinuousEnvironment env;
    env.ended_metric = "collision_fraction";
    for (const MetricSpec& spec : continuous_metric_specs(env, ContinuousProtocol{})) {
      result.push_back(spec.name);
    }
    return result;
  }();
  return names;
}

RunRecord run_khepera(const KheperaTaskConfig& config, const JobSpec& job, std::int32_t run,
                      std::span<const SweepPoint> points) {
  const khepera::Khepera robot(config.simulator);
  return run_continuous_protocol(khepera_environment(robot), config.protocol, job, run, points);
}

RunMemoryEstimate estimate_khepera_run(const KheperaTaskConfig& config, const JobSpec& job) {
  ContinuousSizes sizes;
  sizes.observation_dimension = khepera::kNumSensors;
  sizes.actions = khepera::kNumActions;
  sizes.trace_dimension = 3.0;
  sizes.stop_flags = 1.0;
  // The arena's arrays for Fig. 4(a): 5 doubles an obstacle at most, and the
  // robot's 8 sensors (3 numbers, 3 rays of 5, a reading).
  sizes.simulator_bytes =
      (static_cast<double>(config.simulator.arena.obstacles.size()) * 5.0 + 8.0 * 19.0 + 9.0) * 8.0;
  return estimate_continuous_run(sizes, config.protocol, job);
}

// The Khepera's own arrays (its arena and robot, its undone steps) and its
// readings' units where they differ from the continuous protocol's.
constexpr std::array kKheperaDatasets = {
    DatasetSpec{"samples/collisions", "sample", "flag",
                "1 if the random step was undone (khepera)"},
    DatasetSpec{"graph/occupied", "node", "flag",
                "1 if a reading has the SOM unit as its BMU (khepera)"},
    DatasetSpec{"som/prototypes", "node,sensor", "IR reading",
                "khepera: the prototype of each SOM unit"},
    DatasetSpec{"som/grid", "node,grid_axis", "index",
                "khepera: (row, column) of each unit on the SOM grid"},
    DatasetSpec{"som/quantization_error", "epoch", "IR reading",
                "khepera: mean distance to the BMU after each epoch"},
    DatasetSpec{"state_units", "state", "node id",
                "khepera: the BMU of every reading of the walks (series k, reading t: row "
                "k (steps + 1) + t)"},
    DatasetSpec{"arena/box", "box_field", "cm", "khepera: min x, min y, max x, max y, walled"},
    DatasetSpec{"arena/segments", "segment,segment_field", "cm", "khepera: a x, a y, b x, b y"},
    DatasetSpec{"arena/rectangles", "rectangle,corner_xy", "cm",
                "khepera: min x, min y, max x, max y"},
    DatasetSpec{"arena/rotated_rectangles", "rectangle,rotated_field", "cm, degrees",
                "khepera: centre x, y, width, height, angle (degrees)"},
    DatasetSpec{"arena/discs", "disc,disc_field", "cm", "khepera: centre x, y, radius"},
    DatasetSpec{"arena/start", "pose", "cm, rad", "khepera: start x, y, heading"},
    DatasetSpec{"robot/radius", "value", "cm", "khepera: the body's radius"},
    DatasetSpec{"robot/sensors", "sensor,mount_field", "cm, degrees",
                "khepera: each IR sensor's mount x, y, heading"},
    DatasetSpec{"robot/start_rays", "ray,ray_field", "cm, flag",
                "khepera: three rays per sensor at the start pose: from x, y, to x, y, seen"},
    DatasetSpec{"robot/start_readings", "sensor", "IR reading",
                "khepera: the noiseless readings at the start pose"},
    DatasetSpec{"fit:unit_policy", "node", "action code",
                "khepera: greedy action at each SOM unit's prototype"},
    DatasetSpec{"fit:evaluation/returns", "episode", "reward",
                "khepera: the return of each evaluation episode"},
    DatasetSpec{"fit:evaluation/trajectory_*", "step,pose", "cm, rad",
                "khepera: x, y, heading of the episode's poses from the start"},
};

TaskDefinition khepera_task_definition() {
  const DatasetSpecs own[] = {{"khepera", kKheperaDatasets}};
  return {{"khepera",
           [](const TomlTableReader& job, const std::filesystem::path& job_dir,
              std::vector<JobInput>& inputs) -> std::any {
             return parse_khepera_table(job, job_dir, inputs);
           }},
          [](const JobSpec& job, std::int32_t run, std::span<const SweepPoint> points) {
            return run_khepera(task_config_as<KheperaTaskConfig>(job), job, run, points);
          },
          [](const JobSpec& job) {
            return estimate_khepera_run(task_config_as<KheperaTaskConfig>(job), job);
          },
          [](const JobSpec& job) {
            return khepera_metric_specs(task_config_as<KheperaTaskConfig>(job));
          },
          continuous_dataset_specs(own)};
}

}  // namespace ggk::engine
