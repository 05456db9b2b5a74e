#include "engine/run/salvage_results.hpp"

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

#include "engine/job/usage_error.hpp"
#include "engine/store/results_verify.hpp"
#include "engine/store/run_store.hpp"

namespace ggk::engine {

namespace fs = std::filesystem;

bool machine_error(const std::string& message) {
  for (const char* cause : {"No space left on device", "File too large", "no room to write",
                            "Permission denied", "Read-only file system", "Disk quota exceeded"}) {
    if (message.find(cause) != std::string::npos) return true;
  }
  return false;
}

fs::path keep_damaged_aside(const fs::path& output) {
  const fs::path folder = output.parent_path();
  const std::string stem = output.stem().string(), extension = output.extension().string();
  int error = 0;
  for (int n = 1; n < 100; ++n) {
    const fs::path kept =
        folder / (stem + ".damaged" + (n > 1 ? "-" + std::to_string(n) : "") + extension);
    if (::link(output.c_str(), kept.c_str()) == 0) return kept;
    error = errno;
    if (error != EEXIST) break;
  }
  throw UsageError("cannot resume " + output.string() +
                   ": it is damaged beyond its runs, and it cannot be kept aside as " +
                   (folder / (stem + ".damaged" + extension)).string() + " (" +
                   std::strerror(error) +
                   ") before a new file replaces it; move it away yourself and run the job "
                   "again without --resume, or copy its readable runs with ggk merge");
}

std::vector<std::vector<std::int32_t>> copy_readable_runs(const Hdf5File& damaged, Hdf5File& fresh,
                                                          const Study& study, SalvageCount& count) {
  std::vector<std::vector<std::int32_t>> copied(study.configurations.size());
  for (std::size_t c = 0; c < study.configurations.size(); ++c) {
    const JobSpec& job = study.configurations[c].job;
    const std::string location = runs_location(job);
    std::vector<std::int32_t> listed;
    try {
      listed = stored_runs(damaged, location, job.runs);
    } catch (const std::runtime_error&) {
      ++count.lost_lists;
      continue;
    }
    count.listed += static_cast<std::int64_t>(listed.size());
    for (const std::int32_t run : listed) {
      const std::string group = run_group(location, run);
      bool whole = false;
      try {
        if (!run_is_complete(damaged, location, run)) continue;  // a run cut by a kill
        whole = !verify_run(damaged, location, run).has_value();
        if (whole) fresh.copy_from(damaged, group, group);
      } catch (const std::runtime_error&) {
        whole = false;
      }
      if (!whole) {
        ++count.unreadable;
        if (fresh.exists(group)) fresh.remove(group);  // a copy that failed midway
        continue;
      }
      copied[c].push_back(run);
      ++count.copied;
    }
  }
  return copied;
}

}  // namespace ggk::engine
