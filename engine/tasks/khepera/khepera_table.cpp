#include "engine/tasks/khepera/khepera_table.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <toml++/toml.h>

#include "engine/job/kernel_width.hpp"
#include "engine/job/task_table.hpp"
#include "engine/single_quoted.hpp"
#include "engine/tasks/continuous_table.hpp"
#include "engine/tasks/geometry_keys.hpp"
#include "sims/khepera/khepera.hpp"

namespace ggk::engine {
namespace {

namespace khepera = sims::khepera;

constexpr std::array<std::string_view, 11> kKheperaKeys = {
    "arena_file",     "arena",         "series", "steps_per_series",
    "test_max_steps", "test_episodes", "robot",  "sensors",
    "motion",         "rewards",       "som"};
constexpr std::array<std::string_view, 5> kArenaKeys = {"min", "max", "walled", "start",
                                                        "obstacles"};
constexpr std::array<std::string_view, 3> kStartKeys = {"x", "y", "heading_deg"};
constexpr std::array<std::string_view, 9> kObstacleKeys = {
    "kind", "a", "b", "min", "max", "center", "size", "angle_deg", "radius"};
constexpr std::array<std::string_view, 3> kSegmentKeys = {"kind", "a", "b"};
constexpr std::array<std::string_view, 3> kRectangleKeys = {"kind", "min", "max"};
constexpr std::array<std::string_view, 4> kRotatedRectangleKeys = {"kind", "center", "size",
                                                                   "angle_deg"};
constexpr std::array<std::string_view, 3> kDiscKeys = {"kind", "center", "radius"};
constexpr std::array<std::string_view, 3> kRobotKeys = {"radius", "wheel_base", "sensors"};
constexpr std::array<std::string_view, 10> kSensorModelKeys = {
    "range",       "side_ray_deg", "response_m",     "response_x0",         "response_c",
    "noise_model", "noise_sd",     "noise_fraction", "detection_threshold", "max_reading"};
constexpr std::array<std::string_view, 3> kNoiseModels = {"proportional", "threshold", "additive"};
constexpr std::array<std::string_view, 4> kMotionKeys = {"step_cm", "turn_deg", "wheel_noise",
                                                         "collision_substeps"};
constexpr std::array<std::string_view, 2> kRewardKeys = {"forward", "collision"};
constexpr std::array<ObstacleKind, 4> kObstacleKindKeys = {{
    {"segment", kSegmentKeys, "kind, a, b"},
    {"rectangle", kRectangleKeys, "kind, min, max"},
    {"rotated_rectangle", kRotatedRectangleKeys, "kind, center, size, angle_deg"},
    {"disc", kDiscKeys, "kind, center, radius"},
}};

// The reader of a sub-table given inline or as [table]: `key` must hold a table.
TomlTableReader required_subtable(const TomlTableReader& table, std::string_view key,
                                  std::span<const std::string_view> known_keys,
                                  const std::string& example) {
  std::optional<TomlTableReader> sub = table.subtable(key, known_keys);
  if (!sub) table.fail(key, "required key is missing (expected " + example + ")");
  return std::move(*sub);
}

khepera::Shape obstacle(const TomlTableReader& table) {
  const std::string kind(obstacle_kind(table, kObstacleKindKeys, kObstacleKeys).name);
  if (kind == "segment") {
    const khepera::Point2 a = point(table, "a");
    const khepera::Point2 b = point(table, "b");
    if (a == b) table.fail("b", "expected the segment's ends a and b to differ");
    return khepera::Segment{a, b};
  }
  if (kind == "rectangle") {
    const khepera::Point2 min = point(table, "min");
    const khepera::Point2 max = point(table, "max");
    if (!(min.x < max.x && min.y < max.y)) {
      table.fail("max", "expected max > min in both coordinates (the rectangle's corners)");
    }
    return khepera::Rectangle{min, max};
  }
  if (kind == "rotated_rectangle") {
    const khepera::Point2 center = point(table, "center");
    const toml::array& size = sized_array(table, "size", 2, "numbers [width, height]");
    const auto wh = numbers_of<2>(table, "size", size, {"width", "height"}, NumberRange::above(0.0),
                                  "a length > 0.0");
    const double angle = table.number("angle_deg", NumberRange{}, 0.0);
    return khepera::RotatedRectangle{center, wh[0], wh[1], angle};
  }
  return khepera::Disc{point(table, "center"), table.number("radius", NumberRange::above(0.0))};
}

// The arena's readers: its table and its obstacles, kept for reporting what the
// built simulator finds wrong.
struct ArenaTables {
  TomlTableReader arena;
  std::vector<TomlTableReader> obstacles;
};

khepera::Arena parse_arena(const ArenaTables& tables) {
  const TomlTableReader& table = tables.arena;
  khepera::Arena arena;
  arena.min = point(table, "min");
  arena.max = point(table, "max");
  if (!(arena.min.x < arena.max.x && arena.min.y < arena.max.y)) {
    table.fail("max", "expected max > min in both coordinates (the arena's box)");
  }
  arena.walled = table.boolean("walled", arena.walled);
  const TomlTableReader start =
      required_subtable(table, "start", kStartKeys, "a table { x, y, heading_deg }");
  arena.start.x = start.number("x", NumberRange{});
  arena.start.y = start.number("y", NumberRange{});
  arena.start.heading = khepera::degrees_to_radians(start.number("heading_deg", NumberRange{}));
  for (const TomlTableReader& reader : tables.obstacles) {
    arena.obstacles.push_back(obstacle(reader));
  }
  return arena;
}

// Eight [x, y, heading_deg] mountings.
std::array<khepera::IrSensor, khepera::kNumSensors> sensor_mountings(const TomlTableReader& robot) {
  const std::string what = "arrays [x, y, heading_deg] (s0..s7)";
  const toml::array& array =
      sized_array(robot, "sensors", static_cast<std::size_t>(khepera::kNumSensors), what);
  std::array<khepera::IrSensor, khepera::kNumSensors> sensors{};
  for (std::size_t i = 0; i < sensors.size(); ++i) {
    const toml::array* mounting = array[i].as_array();
    if (mounting == nullptr || mounting->size() != 3) {
      robot.fail_at(array[i], "sensors",
                    "expected sensor s" + std::to_string(i) + " as [x, y, heading_deg], got " +
                        describe_value(array[i]) +
                        (mounting ? " of " + std::to_string(mounting->size()) + " elements" : ""));
    }
    const auto values = numbers_of<3>(robot, "sensors", *mounting, {"x", "y", "heading_deg"},
                                      NumberRange{}, "a finite number");
    sensors[i] = {values[0], values[1], values[2]};
  }
  return sensors;
}

khepera::RobotBody parse_robot(const TomlTableReader& robot) {
  khepera::RobotBody body;
  body.radius = robot.number("radius", NumberRange::above(0.0), body.radius);
  body.wheel_base = robot.number("wheel_base", NumberRange::above(0.0), body.wheel_base);
  if (robot.has("sensors")) body.sensors = sensor_mountings(robot);
  return body;
}

khepera::SensorModel parse_sensor_model(const TomlTableReader& table) {
  khepera::SensorModel model;
  model.range = table.number("range", NumberRange::above(0.0), model.range);
  model.side_ray_deg =
      table.number("side_ray_deg", NumberRange::half_open(0.0, 90.0), model.side_ray_deg);
  model.response_m = table.number("response_m", NumberRange::above(0.0), model.response_m);
  model.response_x0 = table.number("response_x0", NumberRange{}, model.response_x0);
  model.response_c = table.number("response_c", NumberRange{}, model.response_c);
  // Each noise model takes its own level keys; a key of another model is an
  // error rather than silently unused (sims/khepera/sensor_model.hpp).
  const std::string noise = table.choice("noise_model", kNoiseModels, "proportional");
  model.noise_model = noise == "threshold"  ? khepera::SensorNoiseModel::threshold
                      : noise == "additive" ? khepera::SensorNoiseModel::additive
                                            : khepera::SensorNoiseModel::proportional;
  const std::string chosen =
      "noise_model is \"" + noise + "\"" + (table.has("noise_model") ? "" : " (the default)");
  if (noise != "proportional" && table.has("noise_fraction")) {
    table.fail("noise_fraction", "applies only to noise_model = \"proportional\"; " + chosen);
  }
  if (noise == "proportional" && table.has("noise_sd")) {
    table.fail("noise_sd",
               "applies only to noise_model = \"threshold\" or \"additive\"; " + chosen);
  }
  if (noise != "threshold" && table.has("detection_threshold")) {
    table.fail("detection_threshold", "applies only to noise_model = \"threshold\"; " + chosen);
  }
  model.noise_fraction =
      table.number("noise_fraction", NumberRange::at_least(0.0), model.noise_fraction);
  model.noise_sd = table.number("noise_sd", NumberRange::at_least(0.0), model.noise_sd);
  model.detection_threshold =
      table.number("detection_threshold", NumberRange::at_least(0.0), model.detection_threshold);
  model.max_reading = table.number("max_reading", NumberRange::above(0.0), model.max_reading);
  const std::string unused = "noise_model is \"" + noise + "\"";
  if (noise != "proportional") table.mark_unused("noise_fraction", unused);
  if (noise == "proportional") table.mark_unused("noise_sd", unused);
  if (noise != "threshold") table.mark_unused("detection_threshold", unused);
  return model;
}

khepera::MotionModel parse_motion(const TomlTableReader& table) {
  khepera::MotionModel motion;
  motion.step_cm = table.number("step_cm", NumberRange::above(0.0), motion.step_cm);
  motion.turn_deg = table.number("turn_deg", NumberRange::open(0.0, 180.0), motion.turn_deg);
  motion.wheel_noise =
      table.number("wheel_noise", NumberRange::half_open(0.0, 1.0), motion.wheel_noise);
  motion.collision_substeps = static_cast<std::int32_t>(
      table.integer("collision_substeps", {1, 1000}, motion.collision_substeps));
  return motion;
}

khepera::Rewards parse_rewards(const TomlTableReader& table) {
  khepera::Rewards rewards;
  rewards.forward = table.number("forward", NumberRange{}, rewards.forward);
  rewards.collision = table.number("collision", NumberRange{}, rewards.collision);
  return rewards;
}

// Builds the simulator once; what check_config or the constructor rejects is
// reported at the key that set the part at fault.
void check_simulator(const khepera::KheperaConfig& config, const TomlTableReader& table,
                     const TomlTableReader& robot, const TomlTableReader& sensors,
                     const TomlTableReader& motion, const TomlTableReader& rewards,
                     const ArenaTables& arena) {
  using Field = khepera::KheperaConfigField;
  try {
    khepera::check_config(config);
    const khepera::Khepera built(config);
  } catch (const khepera::KheperaConfigError& error) {
    const std::string detail = error.what();
    const auto index = static_cast<std::size_t>(std::max(error.index(), 0));
    switch (error.field()) {
      case Field::body:
        robot.fail_table(detail);
      case Field::sensors:
        if (const toml::node* node = robot.find("sensors");
            node && node->as_array() && index < node->as_array()->size()) {
          robot.fail_at((*node->as_array())[index], "sensors", detail);
        }
        // The default mountings: the body radius is too small for them.
        robot.fail("radius", detail +
                                 " (the default Khepera I mountings; give sensors for a "
                                 "smaller body)");
      case Field::sensor_model:
        sensors.fail(sensors.has("response_c") ? "response_c" : "response_x0", detail);
      case Field::motion:
        motion.fail_table(detail);
      case Field::rewards:
        rewards.fail_table(detail);
      case Field::arena_box:
        arena.arena.fail("max", detail);
      case Field::obstacles:
        if (index < arena.obstacles.size()) arena.obstacles[index].fail_table(detail);
        arena.arena.fail("obstacles", detail);
      case Field::start:
        arena.arena.fail("start", detail);
      case Field::protocol:
        table.fail("steps_per_series", detail);
    }
    table.fail_table(detail);
  }
}

// Readings lie in [0, max_reading]^8: none are farther apart than the box's
// diagonal. They are continuous, so there is no smallest distance between
// distinct ones; the check takes a millionth of the sensor range, below any
// sensor's resolution. A kernel's distance is at most a shortest path over the
// SOM's units (fewer edges than units) plus a best-match distance; prototypes
// may lie outside the box (the principal-components initialisation spans the
// samples' spread), allowed for with a factor of 10 on every edge.
DistanceScale khepera_distance_scale(const KheperaTaskConfig& config, std::int64_t readings) {
  const double max_reading = config.simulator.sensors.max_reading;
  const double diagonal = std::sqrt(static_cast<double>(sims::khepera::kNumSensors)) * max_reading;
  const kernels::SomOptions& som = config.protocol.som;
  const std::int64_t units =
      config.protocol.som_grid_from_samples ? readings : std::int64_t{som.rows} * som.cols;
  return {max_reading * 1e-6, 10.0 * static_cast<double>(units + 1) * diagonal,
          "a millionth of the sensor range max_reading",
          "the SOM's units times 10 times the diagonal of the readings' range"};
}

}  // namespace

KheperaTaskConfig parse_khepera_table(const TomlTableReader& job,
                                      const std::filesystem::path& job_dir,
                                      std::vector<JobInput>& inputs) {
  const std::optional<TomlTableReader> table = job.subtable("khepera", kKheperaKeys);
  if (!table) job.fail("khepera", "required table [khepera] is missing (task = \"khepera\")");
  KheperaTaskConfig config;
  khepera::KheperaConfig& simulator = config.simulator;

  // The protocol first: the SOM's size is checked against it.
  ContinuousProtocol& protocol = config.protocol;
  protocol.series = simulator.series;
  protocol.steps_per_series = simulator.steps_per_series;
  protocol.test_max_steps = simulator.test_max_steps;
  protocol.test_episodes = simulator.test_episodes;
  read_continuous_walks(*table, protocol);
  simulator.series = protocol.series;
  simulator.steps_per_series = protocol.steps_per_series;
  simulator.test_max_steps = protocol.test_max_steps;
  simulator.test_episodes = protocol.test_episodes;
  const std::int64_t readings =
      std::int64_t{simulator.series} * (std::int64_t{simulator.steps_per_series} + 1);

  const TomlTableReader robot = table->subtable_or_empty("robot", kRobotKeys);
  simulator.body = parse_robot(robot);
  const TomlTableReader sensors = table->subtable_or_empty("sensors", kSensorModelKeys);
  simulator.sensors = parse_sensor_model(sensors);
  const TomlTableReader motion = table->subtable_or_empty("motion", kMotionKeys);
  simulator.motion = parse_motion(motion);
  const TomlTableReader rewards = table->subtable_or_empty("rewards", kRewardKeys);
  simulator.rewards = parse_rewards(rewards);
  read_som(*table, protocol);
  check_kernel_widths(job, khepera_distance_scale(config, readings));

  // The arena: exactly one of [khepera.arena] and arena_file.
  if (table->has("arena") && table->has("arena_file")) {
    table->fail("arena_file", "give either arena_file or a [khepera.arena] table, not both");
  }
  if (table->has("arena")) {
    ArenaTables arena{required_subtable(*table, "arena", kArenaKeys, "a table"), {}};
    arena.obstacles = obstacle_tables(arena.arena, kObstacleKindKeys, kObstacleKeys);
    simulator.arena = parse_arena(arena);
    check_simulator(simulator, *table, robot, sensors, motion, rewards, arena);
    return config;
  }
  if (!table->has("arena_file")) {
    table->fail_table(
        "the arena is missing: give arena_file = \"arenas/default.toml\" (relative to the job "
        "file) or a [khepera.arena] table");
  }
  const std::string arena_file = table->string("arena_file");
  if (arena_file.empty()) table->fail("arena_file", "expected a file name, got \"\"");
  inputs.push_back(read_job_input(*table, "arena_file", job_dir, arena_file, "arena file"));
  const std::string& text = inputs.back().text;
  // Errors inside the arena file name that file, its line and its key, and say
  // which job read it.
  const std::string file = inputs.back().path;
  try {
    toml::table root;
    try {
      root = toml::parse(std::string_view(text), std::string_view(file));
    } catch (const toml::parse_error& error) {
      throw JobError(file, location_of(error.source()), "",
                     "TOML syntax error: " + std::string(error.description()));
    }
    ArenaTables arena{TomlTableReader(root, "", file, kArenaKeys), {}};
    arena.obstacles = obstacle_tables(arena.arena, kObstacleKindKeys, kObstacleKeys);
    simulator.arena = parse_arena(arena);
    check_simulator(simulator, *table, robot, sensors, motion, rewards, arena);
  } catch (const JobError& error) {
    if (error.file() != file) throw;
    throw JobError(error.file(), {error.line(), error.column()}, error.key_path(),
                   error.detail() + " (the arena_file of " + single_quoted(table->file()) + ")");
  }
  return config;
}

}  // namespace ggk::engine
