#include "engine/run/shards.hpp"

#include <charconv>
#include <cstdlib>
#include <map>
#include <optional>
#include <set>
#include <system_error>

#include "engine/job/job_file.hpp"
#include "engine/job/usage_error.hpp"
#include "engine/run/adaptive_shards.hpp"
#include "engine/tasks/task_list.hpp"

namespace ggk::engine {
namespace {

namespace fs = std::filesystem;

// A whole non-negative decimal number, nothing around it.
std::optional<std::int32_t> parse_count(std::string_view text) {
  std::int32_t value = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc() || end != text.data() + text.size() || text.empty() || value < 0) {
    return std::nullopt;
  }
  return value;
}

// A Slurm variable as a number; nullopt when unset, UsageError when not a number.
std::optional<std::int32_t> slurm_number(const EnvironmentLookup& environment, const char* name) {
  const char* value = environment(name);
  if (value == nullptr) return std::nullopt;
  const auto number = parse_count(value);
  if (!number) {
    throw UsageError(std::string("--shard slurm: ") + name + "=" + value +
                     " is not a whole number >= 0");
  }
  return number;
}

Shard shard_from_slurm(const EnvironmentLookup& environment) {
  const std::string help =
      " (--shard slurm needs an array 0..N-1 in steps of 1, e.g. sbatch --array=0-3 for 4 "
      "shards; or give the shard as --shard I/N)";
  const auto id = slurm_number(environment, "SLURM_ARRAY_TASK_ID");
  if (!id) {
    throw UsageError(
        "--shard slurm: SLURM_ARRAY_TASK_ID is not set: this is not a task of a Slurm job "
        "array (sbatch --array=0-3 ...); outside one, give the shard as --shard I/N");
  }
  const auto min = slurm_number(environment, "SLURM_ARRAY_TASK_MIN");
  const auto max = slurm_number(environment, "SLURM_ARRAY_TASK_MAX");
  const auto count = slurm_number(environment, "SLURM_ARRAY_TASK_COUNT");
  const auto step = slurm_number(environment, "SLURM_ARRAY_TASK_STEP");
  if (!count && !max) {
    throw UsageError(
        "--shard slurm: SLURM_ARRAY_TASK_ID is set but neither SLURM_ARRAY_TASK_COUNT nor "
        "SLURM_ARRAY_TASK_MAX: the array's size is unknown" +
        help);
  }
  if (min && *min != 0) {
    throw UsageError("--shard slurm: the array starts at " + std::to_string(*min) +
                     " (SLURM_ARRAY_TASK_MIN=" + std::to_string(*min) + "), not 0" + help);
  }
  if (step && *step != 1) {
    throw UsageError("--shard slurm: the array goes in steps of " + std::to_string(*step) +
                     " (SLURM_ARRAY_TASK_STEP=" + std::to_string(*step) + ")" + help);
  }
  if (count && max && *count != *max + 1) {
    throw UsageError("--shard slurm: the array has " + std::to_string(*count) +
                     " tasks (SLURM_ARRAY_TASK_COUNT) but ends at " + std::to_string(*max) +
                     " (SLURM_ARRAY_TASK_MAX): a list with gaps" + help);
  }
  const std::int32_t tasks = count ? *count : *max + 1;
  if (*id >= tasks) {
    throw UsageError("--shard slurm: SLURM_ARRAY_TASK_ID=" + std::to_string(*id) +
                     " is outside the array 0.." + std::to_string(tasks - 1) + help);
  }
  return {*id, tasks};
}

}  // namespace

Shard parse_shard(std::string_view text, const EnvironmentLookup& environment) {
  if (text == "slurm") return shard_from_slurm(environment);
  const std::string usage = "--shard " + std::string(text) +
                            ": expected I/N, shard I of N with 0 <= I < N (e.g. --shard 0/4), "
                            "or 'slurm' in a Slurm job array";
  const std::size_t slash = text.find('/');
  if (slash == std::string_view::npos) throw UsageError(usage);
  const auto index = parse_count(text.substr(0, slash));
  const auto count = parse_count(text.substr(slash + 1));
  if (!index || !count) throw UsageError(usage);
  if (*count == 0 || *index >= *count) {
    throw UsageError("--shard " + std::string(text) + ": shard " + std::to_string(*index) + " of " +
                     std::to_string(*count) + " does not exist (shards are numbered 0.." +
                     (*count == 0 ? std::string("N-1, N >= 1") : std::to_string(*count - 1)) + ")");
  }
  return {*index, *count};
}

RunRange shard_runs(const Shard& shard, std::int32_t runs) {
  if (shard.count > runs) {
    throw UsageError("--shard " + std::to_string(shard.index) + "/" + std::to_string(shard.count) +
                     ": the job has " + std::to_string(runs) + " runs, fewer than " +
                     std::to_string(shard.count) +
                     " shards (a shard would have no run): use at "
                     "most " +
                     std::to_string(runs) + " shards");
  }
  return shard_range(shard, runs);
}

RunRange shard_range(const Shard& shard, std::int32_t items) {
  const auto boundary = [&](std::int64_t index) {
    return static_cast<std::int32_t>(index * items / shard.count);
  };
  return {boundary(shard.index), boundary(std::int64_t{shard.index} + 1)};
}

fs::path shard_output(const fs::path& output, const Shard& shard) {
  fs::path name = output.stem();
  name += ".shard-" + std::to_string(shard.index) + "-of-" + std::to_string(shard.count);
  name += output.extension();
  return output.parent_path() / name;
}

void select_shard(const Shard& shard, const JobSpec& job, RunOptions& options) {
  options.runs = shard_runs(shard, job.runs);
  options.output = shard_output(options.output.empty() ? job.output.file : options.output, shard);
}

void apply_shard_option(std::string_view text, const fs::path& job_path, JobLoadOptions load,
                        RunOptions& options) {
  load.check_output = false;  // the shard's file is checked when it is opened
  const Study study = load_study(job_path, task_tables(), load);
  const JobSpec& job = study.job();
  const auto environment = [](const char* name) -> const char* { return std::getenv(name); };
  const Shard shard = parse_shard(text, environment);
  if (job.adaptive) {
    select_adaptive_shard(shard, study, options);  // by configurations
  } else {
    select_shard(shard, job, options);
  }
}

std::vector<fs::path> shards_of_job(const fs::path& job_path, JobLoadOptions load,
                                    std::string& output, bool allow_missing) {
  load.check_output = false;
  const Study study = load_study(job_path, task_tables(), load);
  if (output.empty() && (!load.overrides.empty() || !load.sweeps.empty())) {
    // ggk run refuses --set / --sweep into the job's own file: the shards were
    // written beside the run's -o.
    throw UsageError("merge --shards-of " + job_path.string() + " with " +
                     (load.sweeps.empty() ? "--set" : "--sweep") +
                     ": the shards of such a run are named after its -o OUT (OUT.shard-I-of-N.h5); "
                     "give the same -o OUT here, or the shard files by name (ggk merge OUT "
                     "OUT.shard-0-of-N.h5 ...)");
  }
  if (output.empty()) output = study.job().output.file.string();
  return find_shards(output, allow_missing);
}

std::vector<fs::path> find_shards(const fs::path& output, bool allow_missing) {
  const fs::path folder = output.parent_path().empty() ? fs::path(".") : output.parent_path();
  const std::string prefix = output.stem().string() + ".shard-";
  const std::string extension = output.extension().string();
  const fs::path pattern = output.parent_path() / (prefix + "I-of-N" + extension);

  // count -> index -> file
  std::map<std::int32_t, std::map<std::int32_t, fs::path>> splits;
  std::error_code error;
  for (fs::directory_iterator entry(folder, error), end; !error && entry != end;
       entry.increment(error)) {
    const std::string name = entry->path().filename().string();
    if (name.size() <= prefix.size() + extension.size() || name.rfind(prefix, 0) != 0 ||
        name.compare(name.size() - extension.size(), extension.size(), extension) != 0) {
      continue;
    }
    const std::string_view middle = std::string_view(name).substr(
        prefix.size(), name.size() - prefix.size() - extension.size());  // "I-of-N"
    const std::size_t of = middle.find("-of-");
    if (of == std::string_view::npos) continue;
    const auto index = parse_count(middle.substr(0, of));
    const auto count = parse_count(middle.substr(of + 4));
    if (!index || !count || *index >= *count) continue;
    // The name as ggk writes it (no leading zeros), so the shard has one name.
    const fs::path file = shard_output(output, {*index, *count});
    if (file.filename() != entry->path().filename()) continue;
    splits[*count][*index] = file;
  }

  if (splits.empty()) {
    throw UsageError("no shards of " + output.string() + ": no file " + pattern.string() + " in " +
                     folder.string() + " (ggk run JOB --shard I/N or --shard slurm writes them)");
  }
  if (splits.size() > 1) {
    std::string described;
    for (const auto& [count, files] : splits) {
      described += (described.empty() ? "" : "; ") + std::to_string(files.size()) + " of " +
                   std::to_string(count) + " (" + files.begin()->second.string() +
                   (files.size() > 1 ? " ..." : "") + ")";
    }
    throw UsageError("shards of " + output.string() + " from " + std::to_string(splits.size()) +
                     " different splits: " + described +
                     "; remove the files of the split that is not wanted");
  }
  const auto& [count, files] = *splits.begin();
  std::vector<fs::path> found;
  std::string missing;
  std::int32_t missing_count = 0;
  for (std::int32_t index = 0; index < count; ++index) {
    const auto file = files.find(index);
    if (file != files.end()) {
      found.push_back(file->second);
    } else {
      ++missing_count;
      missing += (missing.empty() ? "" : ", ") + shard_output(output, {index, count}).string();
    }
  }
  if (missing_count > 0 && !allow_missing) {
    throw UsageError(std::to_string(missing_count) + " of " + std::to_string(count) +
                     " shards of " + output.string() + " missing: " + missing +
                     " (ggk run JOB --shard I/" + std::to_string(count) +
                     " --resume computes shard I; ggk merge --allow-partial merges the others)");
  }
  return found;
}

}  // namespace ggk::engine
