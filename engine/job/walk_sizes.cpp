#include "engine/job/walk_sizes.hpp"

#include <limits>
#include <string>

namespace ggk::engine {

WalkSizes read_walk_sizes(const TomlTableReader& table, WalkSizes defaults, WalkIds ids) {
  constexpr std::int64_t kInt32Max = std::numeric_limits<std::int32_t>::max();
  WalkSizes sizes;
  sizes.series =
      static_cast<std::int32_t>(table.integer("series", {1, kInt32Max}, defaults.series));
  sizes.steps_per_series = static_cast<std::int32_t>(
      table.integer("steps_per_series", {1, kInt32Max}, defaults.steps_per_series));
  const std::int64_t series = sizes.series, steps = sizes.steps_per_series;
  if (ids == WalkIds::kSamples && series * steps > kInt32Max) {
    table.fail("steps_per_series", "series x steps_per_series = " + std::to_string(series * steps) +
                                       " samples per run, more than " + std::to_string(kInt32Max));
  }
  if (ids == WalkIds::kReadings && series * (steps + 1) > kInt32Max) {
    table.fail("steps_per_series",
               "series x (steps_per_series + 1) = " + std::to_string(series * (steps + 1)) +
                   " readings per run, more than " + std::to_string(kInt32Max));
  }
  return sizes;
}

}  // namespace ggk::engine
