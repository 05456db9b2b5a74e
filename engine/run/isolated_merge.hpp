#pragma once
// `ggk merge` with its reading of the shards in a child process
// (isolated_reading.hpp): a shard that crashes the HDF5 library is named and
// refused like any damaged shard, and what the crashed merge left (its
// `OUT.merging-<pid>` file, its lock) is removed, so OUT is either the whole
// merge or not there.

#include <filesystem>
#include <ostream>
#include <span>

#include "engine/store/results_merge.hpp"

namespace ggk::engine {

// merge_results in a child; returns 0. Throws what merge_results throws; a crash
// is a UsageError naming the shard that crashes when read alone.
int merge_results_isolated(const std::filesystem::path& output,
                           std::span<const std::filesystem::path> shards,
                           const MergeOptions& options, std::ostream& log);

}  // namespace ggk::engine
