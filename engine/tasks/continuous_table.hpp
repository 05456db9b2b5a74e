#pragma once
// The continuous protocol's keys (continuous_protocol.hpp), read the same way
// in every continuous task's table: the walks (`series`, `steps_per_series`),
// the test (`test_episodes`, `test_max_steps`), the self-organising map
// ([<task>.som]: rows, cols or grid_from_samples, epochs, radii, schedule,
// initialisation) and the per-dimension scale ([<task>.scale]: one number per
// observation dimension, by name). A task's parser calls read_continuous_protocol
// (or its parts, in its own order) and then check_kernel_widths with
// continuous_distance_scale.

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "engine/job/kernel_width.hpp"
#include "engine/job/toml_table_reader.hpp"
#include "engine/tasks/continuous_protocol.hpp"

namespace ggk::engine {

// The keys read_continuous_protocol reads from the task's table (a task's table
// knows these and its own).
inline constexpr std::array<std::string_view, 6> kContinuousProtocolKeys = {
    "series", "steps_per_series", "test_episodes", "test_max_steps", "som", "scale"};

// One observation dimension: its name (the key of [<task>.scale]), its default
// scale (the task's documented range) and what the default is, for the docs.
struct ObservationDimension {
  std::string_view name;
  double default_scale = 1.0;
};

// series, steps_per_series (ids of the observations: series x (steps + 1) fit
// 32 bits), test_max_steps and test_episodes, `protocol`'s values the defaults.
void read_continuous_walks(const TomlTableReader& table, ContinuousProtocol& protocol);

// [<task>.som] of `task_table`: sets protocol.som and som_grid_from_samples
// (default: the protocol's); a grid with more units than observations per run
// is refused at rows / cols, or at the walk sizes for the default grid.
void read_som(const TomlTableReader& task_table, ContinuousProtocol& protocol);

// [<task>.scale]: one number > 0 per dimension (default: its default_scale).
std::vector<double> read_scale(const TomlTableReader& task_table,
                               std::span<const ObservationDimension> dimensions);

// All of the above, in this order, with `defaults` as the defaults.
ContinuousProtocol read_continuous_protocol(const TomlTableReader& task_table,
                                            ContinuousProtocol defaults,
                                            std::span<const ObservationDimension> dimensions);

// The distances the protocol's kernels meet, in scaled units, for observations
// that lie in a box of `span` scaled units per dimension (1 when the scale is
// each dimension's range): no two distinct ones closer than a millionth of a
// unit; none farther than a shortest path over the SOM's units (fewer edges than
// units) plus a best-match distance, each within 10 diagonals of the box
// (prototypes and observations may leave it a little).
DistanceScale continuous_distance_scale(const ContinuousProtocol& protocol, std::int32_t dimension,
                                        double span = 1.0);

}  // namespace ggk::engine
