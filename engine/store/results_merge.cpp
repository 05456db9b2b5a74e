#include "engine/store/results_merge.hpp"

#include <unistd.h>

#include <map>
#include <optional>
#include <string>
#include <system_error>
#include <vector>

#include "engine/job/job_compare.hpp"
#include "engine/job/usage_error.hpp"
#include "engine/store/hdf5_file.hpp"
#include "engine/store/output_lock.hpp"
#include "engine/store/run_store.hpp"

namespace ggk::engine {

namespace {

struct Shard {
  std::filesystem::path path;
  Hdf5File file;
};

Hdf5File open_shard(const std::filesystem::path& path) {
  try {
    Hdf5File file = Hdf5File::open_read_only(path);
    for (const char* attribute : {"job", "task", "runs"}) {
      if (!file.has_attribute("/", attribute)) {
        throw UsageError(path.string() + " is not a ggk results file (no '" + attribute +
                         "' attribute)");
      }
    }
    return file;
  } catch (const UsageError&) {
    throw;
  } catch (const std::exception& e) {
    throw UsageError(e.what());
  }
}

// The root attributes that say which job a file holds besides the job text
// itself (compared as parsed TOML): the task and the inputs' texts.
std::map<std::string, std::string> job_identity(const Hdf5File& file) {
  std::map<std::string, std::string> identity;
  for (const std::string& name : file.attribute_names("/")) {
    if (name == "task" || name.rfind("input:", 0) == 0) {
      identity[name] = file.read_string_attribute("/", name);
    }
  }
  return identity;
}

// "3, 5-9, 12" from ascending run ids.
std::string ranges(const std::vector<std::int32_t>& runs) {
  std::string text;
  for (std::size_t i = 0; i < runs.size();) {
    std::size_t j = i;
    while (j + 1 < runs.size() && runs[j + 1] == runs[j] + 1) ++j;
    if (!text.empty()) text += ", ";
    text += std::to_string(runs[i]);
    if (j > i) text += "-" + std::to_string(runs[j]);
    i = j + 1;
  }
  return text;
}

}  // namespace

void merge_results(const std::filesystem::path& output,
                   std::span<const std::filesystem::path> shard_paths, const MergeOptions& options,
                   std::ostream& log) {
  std::error_code error;
  const OutputLock lock = OutputLock::acquire(output);  // one writer per output
  if (std::filesystem::exists(output, error)) {
    throw UsageError("merge output " + output.string() +
                     " exists; ggk merge writes a new file (remove it, or choose another name)");
  }
  std::vector<Shard> shards;
  for (const std::filesystem::path& path : shard_paths) {
    for (const Shard& earlier : shards) {
      if (std::filesystem::equivalent(earlier.path, path, error)) {
        throw UsageError(path.string() + " is named twice");
      }
    }
    shards.push_back({path, open_shard(path)});
  }
  const Hdf5File& first = shards.front().file;
  const std::string task = first.read_string_attribute("/", "task");
  const auto runs = static_cast<std::int32_t>(first.read_int64_attribute("/", "runs"));
  const auto identity = job_identity(first);
  const std::string job_text = first.read_string_attribute("/", "job");
  for (const Shard& shard : shards) {
    std::optional<std::string> difference =
        job_difference(job_text, shard.file.read_string_attribute("/", "job"),
                       shards.front().path.string(), shard.path.string());
    if (!difference && job_identity(shard.file) != identity) difference = "its input files differ";
    if (difference) {
      throw UsageError(shard.path.string() + " holds another job than " +
                       shards.front().path.string() + " (" + *difference +
                       "): only shards of one job merge");
    }
  }

  // Which shard holds each complete run.
  std::vector<std::optional<std::size_t>> owner(static_cast<std::size_t>(runs));
  for (std::size_t s = 0; s < shards.size(); ++s) {
    for (std::int32_t run = 0; run < runs; ++run) {
      if (!run_is_complete(shards[s].file, task, run)) continue;
      auto& held = owner[static_cast<std::size_t>(run)];
      if (held) {
        throw UsageError("run " + std::to_string(run) + " is complete in both " +
                         shards[*held].path.string() + " and " + shards[s].path.string() +
                         ": overlapping shards (give each run to one shard)");
      }
      held = s;
    }
  }
  std::vector<std::int32_t> missing;
  for (std::int32_t run = 0; run < runs; ++run) {
    if (!owner[static_cast<std::size_t>(run)]) missing.push_back(run);
  }
  if (!missing.empty() && !options.allow_partial) {
    throw UsageError(std::to_string(missing.size()) + " of " + std::to_string(runs) +
                     " runs are complete in no shard: " + ranges(missing) +
                     "; compute them (ggk run --runs A:B), or pass --allow-partial to merge "
                     "what exists and let `ggk run JOB --resume -o " +
                     output.string() + "` fill them in");
  }

  // Written under a temporary name, renamed into place when whole.
  const std::filesystem::path temporary =
      output.string() + ".merging-" + std::to_string(::getpid());
  try {
    Hdf5File merged = [&] {
      try {
        return Hdf5File::create(temporary, Hdf5File::CreateMode::kFailIfExists);
      } catch (const std::exception& e) {
        throw UsageError(e.what());
      }
    }();
    for (const std::string& name : first.attribute_names("/")) {
      if (name == "runs_selected") continue;  // the merged file is the whole job's
      if (name == "runs") {
        merged.write_int64_attribute("/", name, runs);
      } else {
        merged.write_string_attribute("/", name, first.read_string_attribute("/", name));
      }
    }
    merged.create_group("/" + task);
    for (std::int32_t run = 0; run < runs; ++run) {
      if (const auto& s = owner[static_cast<std::size_t>(run)]) {
        merged.copy_from(shards[*s].file, run_group(task, run), run_group(task, run));
      }
    }
    write_summary(merged, task, runs);
    merged.flush();
  } catch (...) {
    std::filesystem::remove(temporary, error);
    throw;
  }
  std::filesystem::rename(temporary, output);
  log << "ggk: merged " << runs - static_cast<std::int32_t>(missing.size()) << " of " << runs
      << " runs from " << shards.size() << " shards into " << output.string() << "\n";
  if (!missing.empty()) {
    log << "ggk: runs missing: " << ranges(missing) << "; finish with `ggk run JOB --resume -o "
        << output.string() << "`\n";
  }
}

}  // namespace ggk::engine
