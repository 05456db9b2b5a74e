#include "engine/tasks/arm/arm_table.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "engine/job/kernel_width.hpp"
#include "engine/job/task_table.hpp"
#include "engine/job/walk_sizes.hpp"
#include "engine/tasks/geometry_keys.hpp"
#include "sims/arm/arm.hpp"

namespace ggk::engine {
namespace {

namespace arm = sims::arm;

constexpr std::array<std::string_view, 11> kArmKeys = {
    "links",  "base",   "shoulder_limits",  "elbow_limits",   "grid_step_degrees", "start_A",
    "object", "series", "steps_per_series", "test_max_steps", "obstacles"};
constexpr std::string_view kGridStepKey = "grid_step_degrees";
constexpr std::array<std::string_view, 2> kObjectKeys = {"center", "radius"};
constexpr std::array<std::string_view, 5> kArmObstacleKeys = {"kind", "min", "max", "center",
                                                              "radius"};
constexpr std::array<std::string_view, 3> kArmRectangleKeys = {"kind", "min", "max"};
constexpr std::array<std::string_view, 3> kArmDiscKeys = {"kind", "center", "radius"};
constexpr std::array<ObstacleKind, 2> kObstacleKinds = {{
    {"rectangle", kArmRectangleKeys, "kind, min, max"},
    {"disc", kArmDiscKeys, "kind, center, radius"},
}};

// The joint grid step in tenths of a degree: grid_step_degrees, a whole number
// of tenths in [0.1, 360), default 5 (the paper's grid).
std::int32_t grid_step(const TomlTableReader& table) {
  if (!table.has(kGridStepKey)) return arm::kPaperGridStepTenths;
  const double degrees = table.number(kGridStepKey, NumberRange{0.1, true, 360.0, false});
  const double scaled = degrees * arm::kTenthsPerDegree;
  const double tenths = std::round(scaled);
  if (std::abs(scaled - tenths) > 1e-9 * tenths) {
    table.fail(kGridStepKey,
               "expected a whole number of tenths of a degree (5, 2.5, 1, 0.5), got " +
                   describe_value(*table.find(kGridStepKey)));
  }
  return static_cast<std::int32_t>(tenths);
}

// [shoulder, elbow] or [min, max] of integer degrees in [-360, 360], each a
// multiple of the grid step (step_tenths). A value on the paper's 5-degree grid
// that a coarser grid_step_degrees misses is the step's fault and reported there.
std::array<std::int32_t, 2> degree_pair(const TomlTableReader& table, std::string_view key,
                                        const std::string& names, std::int32_t step_tenths,
                                        std::optional<std::array<std::int32_t, 2>> fallback = {}) {
  const std::string step = arm::grid_step_text(step_tenths);
  std::array<std::int32_t, 2> pair{};
  if (!table.has(key) && fallback) {
    pair = *fallback;
  } else {
    const toml::array& array = sized_array(table, key, 2, "integers " + names + " in degrees");
    for (std::size_t i = 0; i < 2; ++i) {
      const toml::node& element = array[i];
      const auto* integer = element.as_integer();
      const std::string expectation =
          "expected integer degrees, multiples of " + step + " in [-360, 360], got ";
      if (integer == nullptr || integer->get() < -360 || integer->get() > 360 ||
          (integer->get() * arm::kTenthsPerDegree % step_tenths != 0 &&
           integer->get() % arm::kJointUnitDegrees != 0)) {
        table.fail_at(element, key, expectation + describe_value(element));
      }
      pair[i] = static_cast<std::int32_t>(integer->get());
    }
  }
  for (const std::int32_t value : pair) {
    if (value * arm::kTenthsPerDegree % step_tenths != 0) {
      table.fail(kGridStepKey, "a grid step of " + step + " degrees does not divide " +
                                   std::string(key) + " [" + std::to_string(pair[0]) + ", " +
                                   std::to_string(pair[1]) +
                                   "]: the joint limits and start_A must be multiples of it");
    }
  }
  return pair;
}

// Joint limits [min, max]: min <= max, spanning less than 360 degrees.
std::array<std::int32_t, 2> limits(const TomlTableReader& table, std::string_view key,
                                   std::int32_t step_tenths, std::array<std::int32_t, 2> fallback) {
  const std::array<std::int32_t, 2> range =
      degree_pair(table, key, "[min, max]", step_tenths, fallback);
  if (range[0] > range[1]) {
    table.fail(key, "expected min <= max, got [" + std::to_string(range[0]) + ", " +
                        std::to_string(range[1]) + "]");
  }
  if (range[1] - range[0] >= 360) {
    table.fail(key, "the limits [" + std::to_string(range[0]) + ", " + std::to_string(range[1]) +
                        "] span 360 degrees or more; the joint does not wrap, so min and " +
                        "max + one grid step would be one pose twice");
  }
  return range;
}

arm::Obstacle arm_obstacle(const TomlTableReader& table) {
  const std::string kind(obstacle_kind(table, kObstacleKinds, kArmObstacleKeys).name);
  if (kind == "rectangle") {
    const arm::Point2 min = point(table, "min");
    const arm::Point2 max = point(table, "max");
    if (min.x > max.x || min.y > max.y) {
      table.fail("max", "expected max >= min in both coordinates (the rectangle's corners)");
    }
    return arm::Rectangle{min, max};
  }
  return arm::Disc{point(table, "center"), table.number("radius", NumberRange::above(0.0))};
}

// State vectors are joint angles in units of 5 degrees: distinct poses are at
// least one grid step (step / 5 units; 1 at the default) apart. A kernel's
// distance is at most a shortest path on the sample graph (fewer than num_states
// edges, each at most the grid's diagonal) plus the Euclidean distance to the
// nearest graph node (at most the diagonal).
DistanceScale arm_distance_scale(const arm::Arm& built) {
  const double step = static_cast<double>(built.grid_step_tenths()) /
                      (arm::kJointUnitDegrees * arm::kTenthsPerDegree);
  const double diagonal = std::hypot(built.shoulder_steps() - 1, built.elbow_steps() - 1);
  return {step, static_cast<double>(built.num_states()) * std::max(diagonal, 1.0) * step,
          "between neighbouring poses", "the number of poses times the joint grid's diagonal"};
}

}  // namespace

arm::ArmConfig parse_arm_table(const TomlTableReader& job) {
  const std::optional<TomlTableReader> table = job.subtable("arm", kArmKeys);
  if (!table) job.fail("arm", "required table [arm] is missing (task = \"arm\")");
  arm::ArmConfig config;
  arm::ArmGeometry& geometry = config.geometry;

  const auto lengths =
      numbers_of<2>(*table, "links", sized_array(*table, "links", 2, "numbers [link1, link2]"),
                    {"link1", "link2"}, NumberRange::above(0.0), "a length > 0.0");
  geometry.link1_length = lengths[0];
  geometry.link2_length = lengths[1];
  geometry.base = point(*table, "base", arm::Point2{});

  config.grid_step_tenths = grid_step(*table);
  const arm::JointLimits defaults;
  const auto shoulder = limits(*table, "shoulder_limits", config.grid_step_tenths,
                               {defaults.shoulder_min_deg, defaults.shoulder_max_deg});
  const auto elbow = limits(*table, "elbow_limits", config.grid_step_tenths,
                            {defaults.elbow_min_deg, defaults.elbow_max_deg});
  config.limits = {shoulder[0], shoulder[1], elbow[0], elbow[1]};
  const auto start = degree_pair(*table, "start_A", "[shoulder, elbow]", config.grid_step_tenths);
  config.start_A = {static_cast<double>(start[0]), static_cast<double>(start[1])};

  const std::vector<TomlTableReader> obstacles =
      obstacle_tables(*table, kObstacleKinds, kArmObstacleKeys);
  for (const TomlTableReader& reader : obstacles) {
    geometry.obstacles.push_back(arm_obstacle(reader));
  }

  const std::optional<TomlTableReader> object = table->subtable("object", kObjectKeys);
  if (!object) table->fail("object", "required table [arm.object] is missing");
  geometry.object = {point(*object, "center"), object->number("radius", NumberRange::above(0.0))};

  const WalkSizes walks = read_walk_sizes(*table, {config.series, config.steps_per_series});
  config.series = walks.series;
  config.steps_per_series = walks.steps_per_series;
  config.test_max_steps = static_cast<std::int32_t>(
      table->integer("test_max_steps", kTestMaxStepsRange, config.test_max_steps));

  // Build the arm: what only the whole geometry can tell (no free pose, no goal,
  // A colliding) is reported at the key that set the part at fault.
  std::optional<arm::Arm> built;
  try {
    built.emplace(config);
  } catch (const arm::ArmConfigError& error) {
    switch (error.field()) {
      case arm::ArmConfigField::links:
        table->fail("links", error.what());
      case arm::ArmConfigField::base:
        table->fail("base", error.what());
      case arm::ArmConfigField::shoulder_limits:
        table->fail("shoulder_limits", error.what());
      case arm::ArmConfigField::elbow_limits:
        table->fail("elbow_limits", error.what());
      case arm::ArmConfigField::grid_step:
        table->fail(kGridStepKey, error.what());
      case arm::ArmConfigField::obstacles:
        if (error.index() >= 0 && static_cast<std::size_t>(error.index()) < obstacles.size()) {
          obstacles[static_cast<std::size_t>(error.index())].fail_table(error.what());
        }
        table->fail("obstacles", error.what());
      case arm::ArmConfigField::object:
        object->fail_table(error.what());
      case arm::ArmConfigField::start_A:
        table->fail("start_A", error.what());
    }
    table->fail_table(error.what());
  }
  check_kernel_widths(job, arm_distance_scale(*built));
  return config;
}

}  // namespace ggk::engine
