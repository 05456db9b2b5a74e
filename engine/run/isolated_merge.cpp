#include "engine/run/isolated_merge.hpp"

#include <system_error>

#include "engine/run/isolated_reading.hpp"
#include "engine/store/output_lock.hpp"

namespace ggk::engine {

int merge_results_isolated(const std::filesystem::path& output,
                           std::span<const std::filesystem::path> shards,
                           const MergeOptions& options, std::ostream& log) {
  const auto clear_after = [&](pid_t child) {
    std::error_code ignored;
    std::filesystem::remove(merging_path(output, child), ignored);
    // The child's lock is stale now that it is gone: taken over and released.
    try {
      OutputLock::acquire(output);
    } catch (const std::exception&) {  // another ggk holds it now: its to remove
    }
  };
  try {
    return read_isolated(
        {shards.begin(), shards.end()},
        [&] {
          merge_results(output, shards, options, log);
          return 0;
        },
        clear_after);
  } catch (const ReadingCrash& crash) {
    throw UsageError(std::string(crash.what()) +
                     "; compute its runs again into a new shard (ggk run with the --runs or "
                     "--shard it was made with), then merge");
  }
}

}  // namespace ggk::engine
