#include "engine/tasks/continuous_table.hpp"

#include <cmath>
#include <limits>
#include <string>

#include "engine/job/task_table.hpp"
#include "engine/job/walk_sizes.hpp"

namespace ggk::engine {

namespace {

constexpr std::array<std::string_view, 8> kSomKeys = {"rows",           "cols",
                                                      "epochs",         "initial_radius",
                                                      "final_radius",   "radius_schedule",
                                                      "initialization", "grid_from_samples"};
constexpr std::array<std::string_view, 2> kRadiusSchedules = {"exponential", "linear"};
constexpr std::array<std::string_view, 2> kInitializations = {"principal_components",
                                                              "random_samples"};
constexpr std::int64_t kSomSideMax = std::numeric_limits<std::int32_t>::max();
// Evaluation episodes per fit: the paper's jobs use 10 (the noise of sensors and
// wheels averaged out); 10^4 is a thousand times that, and beyond it a job is
// one that never ends.
constexpr IntegerRange kTestEpisodesRange{1, 10'000};
// Batch SOM epochs: the map settles in tens (the paper's jobs use 30); each epoch
// reads every observation against every unit, so 10^4 epochs already cost
// minutes per run.
constexpr IntegerRange kSomEpochsRange{1, 10'000};

std::int64_t observations_per_run(const ContinuousProtocol& protocol) {
  return std::int64_t{protocol.series} * (std::int64_t{protocol.steps_per_series} + 1);
}

}  // namespace

void read_continuous_walks(const TomlTableReader& table, ContinuousProtocol& protocol) {
  const WalkSizes walks =
      read_walk_sizes(table, {protocol.series, protocol.steps_per_series}, WalkIds::kReadings);
  protocol.series = walks.series;
  protocol.steps_per_series = walks.steps_per_series;
  protocol.test_max_steps = static_cast<std::int32_t>(
      table.integer("test_max_steps", kTestMaxStepsRange, protocol.test_max_steps));
  protocol.test_episodes = static_cast<std::int32_t>(
      table.integer("test_episodes", kTestEpisodesRange, protocol.test_episodes));
}

void read_som(const TomlTableReader& task_table, ContinuousProtocol& protocol) {
  const TomlTableReader table = task_table.subtable_or_empty("som", kSomKeys);
  const std::int64_t readings = observations_per_run(protocol);
  kernels::SomOptions& som = protocol.som;
  // A grid given by rows or cols is the grid unless grid_from_samples says otherwise.
  const bool grid_given = table.has("rows") || table.has("cols");
  protocol.som_grid_from_samples =
      table.boolean("grid_from_samples", protocol.som_grid_from_samples && !grid_given);
  if (protocol.som_grid_from_samples) {
    for (const std::string_view key : {"rows", "cols"}) {
      if (table.has(key)) {
        table.fail(key,
                   "the grid is derived from the samples (grid_from_samples = true); "
                   "remove rows and cols, or set grid_from_samples = false");
      }
    }
  } else {
    som.rows = static_cast<std::int32_t>(table.integer("rows", {1, kSomSideMax}, som.rows));
    som.cols = static_cast<std::int32_t>(table.integer("cols", {1, kSomSideMax}, som.cols));
    const std::int64_t units = std::int64_t{som.rows} * som.cols;
    if (units > readings) {
      const std::string detail =
          "rows x cols = " + std::to_string(som.rows) + " x " + std::to_string(som.cols) + " = " +
          std::to_string(units) + " units, more than the " + std::to_string(readings) +
          " readings per run (series x (steps_per_series + 1)) the map is trained on";
      if (table.has("rows")) table.fail("rows", detail);
      if (table.has("cols")) table.fail("cols", detail);
      // The default grid: blame the protocol that made the run too small.
      const std::string hint =
          "; set [" + task_table.table_path() + ".som] rows and cols, or grid_from_samples = true";
      if (task_table.has("steps_per_series")) task_table.fail("steps_per_series", detail + hint);
      if (task_table.has("series")) task_table.fail("series", detail + hint);
      task_table.fail_table(detail + hint);
    }
  }
  som.epochs = static_cast<std::int32_t>(table.integer("epochs", kSomEpochsRange, som.epochs));
  som.final_radius = table.number("final_radius", NumberRange::above(0.0), som.final_radius);
  if (table.has("initial_radius")) {
    som.initial_radius = table.number("initial_radius", NumberRange::above(0.0));
    if (*som.initial_radius < som.final_radius) {
      const std::string final_radius = table.has("final_radius")
                                           ? describe_value(*table.find("final_radius"))
                                           : "1.0, its default";
      table.fail("initial_radius", "expected a number >= final_radius (" + final_radius +
                                       "), got " + describe_value(*table.find("initial_radius")));
    }
  }
  som.radius_schedule = table.choice("radius_schedule", kRadiusSchedules, "exponential") == "linear"
                            ? kernels::SomRadiusSchedule::linear
                            : kernels::SomRadiusSchedule::exponential;
  som.initialization =
      table.choice("initialization", kInitializations, "principal_components") == "random_samples"
          ? kernels::SomInitialization::random_samples
          : kernels::SomInitialization::principal_components;
}

std::vector<double> read_scale(const TomlTableReader& task_table,
                               std::span<const ObservationDimension> dimensions) {
  std::vector<std::string_view> names;
  for (const ObservationDimension& dimension : dimensions) names.push_back(dimension.name);
  const TomlTableReader table = task_table.subtable_or_empty("scale", names);
  std::vector<double> scale;
  for (const ObservationDimension& dimension : dimensions) {
    scale.push_back(table.number(dimension.name, NumberRange::above(0.0), dimension.default_scale));
  }
  return scale;
}

ContinuousProtocol read_continuous_protocol(const TomlTableReader& task_table,
                                            ContinuousProtocol defaults,
                                            std::span<const ObservationDimension> dimensions) {
  ContinuousProtocol protocol = std::move(defaults);
  read_continuous_walks(task_table, protocol);
  read_som(task_table, protocol);
  protocol.scale = read_scale(task_table, dimensions);
  return protocol;
}

DistanceScale continuous_distance_scale(const ContinuousProtocol& protocol, std::int32_t dimension,
                                        double span) {
  const double diagonal = std::sqrt(static_cast<double>(dimension)) * span;
  const std::int64_t units = protocol.som_grid_from_samples
                                 ? observations_per_run(protocol)
                                 : std::int64_t{protocol.som.rows} * protocol.som.cols;
  return {span * 1e-6, 10.0 * static_cast<double>(units + 1) * diagonal,
          "a millionth of a scaled unit (observation / scale)",
          "the SOM's units times 10 times the diagonal of the scaled observations' box"};
}

}  // namespace ggk::engine
