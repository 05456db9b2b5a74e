#pragma once
// The random walks' keys every task table has: `series` (walks per run) and
// `steps_per_series` (random actions per walk), integers >= 1, and the check
// that a run's ids fit 32 bits.

#include <cstdint>

#include "engine/job/toml_table_reader.hpp"

namespace ggk::engine {

struct WalkSizes {
  std::int32_t series = 1;
  std::int32_t steps_per_series = 1;
};

// What the run numbers with 32-bit ids: its samples (series x steps_per_series)
// or its readings (series x (steps_per_series + 1): each walk's start too).
enum class WalkIds { kSamples, kReadings };

// Reads series and steps_per_series of `table` (absent: `defaults`); throws
// JobError at the key, or at steps_per_series when the run's ids would pass
// 2^31 - 1.
WalkSizes read_walk_sizes(const TomlTableReader& table, WalkSizes defaults,
                          WalkIds ids = WalkIds::kSamples);

}  // namespace ggk::engine
