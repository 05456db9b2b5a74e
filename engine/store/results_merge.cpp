#include "engine/store/results_merge.hpp"

#include <unistd.h>
#include <chrono>

#include <algorithm>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <system_error>
#include <vector>

#include "engine/hdf5/hdf5_file.hpp"
#include "engine/job/job_compare.hpp"
#include "engine/job/job_error.hpp"
#include "engine/job/shell_words.hpp"
#include "engine/job/usage_error.hpp"
#include "engine/store/adaptive_state.hpp"
#include "engine/store/output_lock.hpp"
#include "engine/store/results_contents.hpp"
#include "engine/store/results_layout.hpp"
#include "engine/store/results_verify.hpp"
#include "engine/store/run_store.hpp"

namespace ggk::engine {

namespace {

struct Shard {
  std::filesystem::path path;
  Hdf5File file;
  ResultsHeader header;
};

// "--sweep a=1,2 --sweep b=x" for the options recorded one a line, "no --sweep"
// for none.
std::string options_words(const std::string& option, const std::string& lines) {
  if (lines.empty()) return "no " + option;
  std::string words;
  std::size_t start = 0;
  while (start <= lines.size()) {
    const std::size_t end = std::min(lines.find('\n', start), lines.size());
    words +=
        (words.empty() ? "" : " ") + option + " " + shell_quoted(lines.substr(start, end - start));
    start = end + 1;
  }
  return words;
}

// `ggk merge --shards-of JOB --set/--sweep ...`: the shard was run with the options
// given (its root attribute job_overrides / job_sweeps, one a line).
void check_run_options(const std::string& option, const std::vector<std::string>& given,
                       const std::string& recorded, const std::filesystem::path& shard) {
  std::string lines;
  for (const std::string& text : given) lines += (lines.empty() ? "" : "\n") + text;
  if (lines == recorded) return;
  throw UsageError(shard.string() + " was run with " + options_words(option, recorded) +
                   ", not the " + options_words(option, lines) +
                   " given here: give the options its run had, or merge the shard files by "
                   "name (ggk merge OUT a.h5 b.h5 ...)");
}

Shard open_shard(const std::filesystem::path& path) {
  try {
    Hdf5File file = Hdf5File::open_waiting_for_lock(path, true, std::chrono::seconds(10));
    ResultsHeader header = read_results_header(file);
    if (const std::string mismatch = layout_mismatch(header.layout); !mismatch.empty()) {
      throw UsageError("cannot merge " + path.string() + ": " + mismatch +
                       "; compute its runs again with this ggk");
    }
    return {path, std::move(file), std::move(header)};
  } catch (const UsageError&) {
    throw;
  } catch (const std::exception& e) {
    throw UsageError(e.what());
  }
}

// The runs in [0, runs) that no shard holds: how many, and as "3, 5-9, 12"
// (the first ranges only).
struct Gaps {
  std::int64_t count = 0;
  std::string text;
};

Gaps gaps(const std::map<std::int32_t, std::size_t>& owner, std::int32_t runs) {
  constexpr int kShownRanges = 20;
  Gaps result;
  int shown = 0;
  const auto add = [&](std::int32_t first, std::int32_t last) {  // inclusive
    if (first > last) return;
    result.count += static_cast<std::int64_t>(last) - first + 1;
    if (shown == kShownRanges) result.text += ", ...";
    if (shown++ >= kShownRanges) return;
    if (!result.text.empty()) result.text += ", ";
    result.text += std::to_string(first);
    if (last > first) result.text += "-" + std::to_string(last);
  };
  std::int32_t next = 0;
  for (const auto& [run, shard] : owner) {
    add(next, run - 1);
    next = run + 1;
  }
  add(next, runs - 1);
  return result;
}

// The command that computes the runs a merged file lacks: the shards' job file
// and overrides (as recorded), --resume onto the merged file.
std::string finish_command(const ResultsHeader& shard, const std::string& program,
                           const std::filesystem::path& output) {
  std::vector<std::string> words = {program, "run"};
  words.push_back(shard.job_file.empty() ? std::string("JOB") : shard.job_file);
  std::istringstream overrides(shard.job_overrides);
  for (std::string text; std::getline(overrides, text);) {
    words.push_back("--set");
    words.push_back(text);
  }
  std::istringstream sweeps(shard.job_sweeps);
  for (std::string text; std::getline(sweeps, text);) {
    words.push_back("--sweep");
    words.push_back(text);
  }
  for (const char* word : {"--resume", "-o"}) words.emplace_back(word);
  words.push_back(output.string());
  return shell_command(words);
}

// Every shard holds the first one's job: the same job text (compared as parsed
// TOML), task, --sweep options and inputs, computed under the same results
// rules, and (options.check_run_options) the --set and --sweep options
// expected. A UsageError names the first shard that differs and how.
void check_one_job(const std::vector<Shard>& shards, const MergeOptions& options) {
  const ResultsHeader& first = shards.front().header;
  for (const Shard& shard : shards) {
    // Besides the job text (compared as parsed TOML), the task and the inputs'
    // texts say which job a file holds.
    std::optional<std::string> difference = job_difference(
        first.job, shard.header.job, shards.front().path.string(), shard.path.string());
    if (!difference && shard.header.task != first.task) difference = "its task differs";
    if (!difference && shard.header.job_sweeps != first.job_sweeps) {
      difference = "its --sweep options differ";
    }
    if (!difference && shard.header.inputs != first.inputs) {
      difference = "its input files differ";
    }
    if (options.check_run_options) {
      check_run_options("--set", options.expected_overrides, shard.header.job_overrides,
                        shard.path);
      check_run_options("--sweep", options.expected_sweeps, shard.header.job_sweeps, shard.path);
    }
    if (shard.header.rules != first.rules) {
      throw UsageError("cannot merge " + shard.path.string() + " with " +
                       shards.front().path.string() + ": its runs were computed under results " +
                       rules_words(shard.header.rules) + ", those of " +
                       shards.front().path.string() + " under " + rules_words(first.rules) +
                       ": merged, they would equal neither ggk's results from scratch");
    }
    if (difference) {
      throw UsageError(shard.path.string() + " holds another job than " +
                       shards.front().path.string() + " (" + *difference +
                       "): only shards of one job merge");
    }
  }
}

// An adaptive study's shard holds runs of its own configurations alone
// (configurations_selected): one of another's is damage, or another file.
void refuse_foreign_configuration(const Shard& shard, std::size_t configuration,
                                  const std::string& location) {
  if (!shard.header.configurations_selected) return;
  const std::vector<std::int64_t>& own = shard.header.configurations_selected->configurations;
  if (std::find(own.begin(), own.end(), static_cast<std::int64_t>(configuration)) == own.end()) {
    throw UsageError(shard.path.string() + " holds runs of " + location +
                     ", a run configuration of another shard of its adaptive study (its own: "
                     "configurations_selected): only the files its shards wrote merge");
  }
}

// Which shard holds each complete run of each location (listed from the files:
// the cost follows what they hold, not the job's run count). A run complete in
// two shards is a UsageError.
std::vector<std::map<std::int32_t, std::size_t>> owners_of_runs(
    const std::vector<Shard>& shards, const std::vector<std::string>& locations,
    const std::string& task, std::int32_t runs) {
  std::vector<std::map<std::int32_t, std::size_t>> owners(locations.size());
  for (std::size_t l = 0; l < locations.size(); ++l) {
    for (std::size_t s = 0; s < shards.size(); ++s) {
      for (const std::int32_t run : complete_runs(shards[s].file, locations[l], runs)) {
        refuse_foreign_configuration(shards[s], l, locations[l]);
        const auto [held, added] = owners[l].emplace(run, s);
        if (!added) {
          throw UsageError("run " + std::to_string(run) +
                           (locations[l] == task ? std::string() : " of " + locations[l]) +
                           " is complete in both " + shards[held->second].path.string() + " and " +
                           shards[s].path.string() +
                           ": overlapping shards (give each run to one shard)");
        }
      }
    }
  }
  return owners;
}

// Nothing copied is trusted unchecked: every run to merge reads back whole
// (checksums, the run's shape: results_verify.hpp) before the output exists.
void verify_runs_to_merge(const std::vector<Shard>& shards,
                          const std::vector<std::string>& locations,
                          const std::vector<std::map<std::int32_t, std::size_t>>& owners,
                          const std::string& task) {
  for (std::size_t l = 0; l < locations.size(); ++l) {
    for (const auto& [run, s] : owners[l]) {
      if (const auto damage = verify_run(shards[s].file, locations[l], run)) {
        throw UsageError(shards[s].path.string() + ": run " + std::to_string(run) +
                         (locations[l] == task ? std::string() : " of " + locations[l]) +
                         " is damaged (" + *damage + "); compute it again with ggk run --resume " +
                         "on that shard (the same command and -o as it was made with), then merge");
      }
    }
  }
}

// The merged file at `temporary`: the first shard's header (as the whole job's),
// each location's configuration attributes and owned runs, copied, and the
// summary.
void write_merged_file(const std::filesystem::path& temporary, const std::vector<Shard>& shards,
                       const std::vector<std::string>& locations,
                       const std::vector<std::map<std::int32_t, std::size_t>>& owners) {
  const ResultsHeader& first = shards.front().header;
  const std::string& task = first.task;
  const auto runs = static_cast<std::int32_t>(first.runs);
  Hdf5File merged = [&] {
    try {
      return Hdf5File::create(temporary, Hdf5File::CreateMode::kFailIfExists);
    } catch (const std::exception& e) {
      throw UsageError(e.what());
    }
  }();
  ResultsHeader header = first;
  header.runs_selected.reset();  // the merged file is the whole job's
  header.configurations_selected.reset();
  write_results_header(merged, header);
  merged.create_group("/" + task);
  for (std::size_t l = 0; l < locations.size(); ++l) {
    if (locations[l] != task) {  // a configuration group's own attributes
      const Hdf5File& source = shards.front().file;
      const std::optional<std::string> values = study_values_of(source, locations[l]);
      if (!values) {
        throw std::runtime_error(source.path().string() + ": /" + locations[l] +
                                 " has no study_values");
      }
      write_configuration_group(merged, locations[l], configuration_of(source, locations[l]),
                                *values);
    }
    for (const auto& [run, s] : owners[l]) {
      merged.copy_from(shards[s].file, run_group(locations[l], run), run_group(locations[l], run));
    }
  }
  write_summary(merged, task, runs);
  merged.flush();
}

// The [adaptive] rule of the shards' job, if it has one.
std::optional<AdaptiveRule> adaptive_rule(const ResultsHeader& header,
                                          const std::filesystem::path& path) {
  try {
    return adaptive_rule_of_text(header.job, path.string() + " (its job)",
                                 static_cast<std::int32_t>(header.runs));
  } catch (const JobError& e) {
    throw UsageError(e.what());
  }
}

// The run configurations an adaptive study's merged file lacks runs of: the
// rule asks for runs 0 .. wanted - 1 and one of them is missing (a shard
// interrupted mid-look may hold run 7 without run 6) or lacks points its open
// cells need (state.needs), as "config_001, config_004".
std::string configurations_lacking_runs(const AdaptiveState& state,
                                        const std::vector<std::string>& locations) {
  std::set<std::int32_t> lacking;
  for (const RunNeed& need : state.needs) lacking.insert(need.configuration);
  std::string text;
  for (const std::int32_t c : lacking) {
    text += (text.empty() ? "" : ", ") + locations[static_cast<std::size_t>(c)];
  }
  return text;
}

// merge_results for an adaptive study's shards: their runs, different in number
// per configuration, merged whole; the merged file is refused unless the rule,
// replayed on it, is done (or allow_partial).
void merge_adaptive_shards(const std::filesystem::path& output, const std::vector<Shard>& shards,
                           const std::vector<std::string>& locations,
                           const std::vector<std::map<std::int32_t, std::size_t>>& owners,
                           const AdaptiveRule& rule, const MergeOptions& options,
                           std::ostream& log) {
  const ResultsHeader& first = shards.front().header;
  verify_runs_to_merge(shards, locations, owners, first.task);
  std::error_code error;
  const std::filesystem::path temporary = merging_path(output, ::getpid());
  std::string lacking;
  try {
    write_merged_file(temporary, shards, locations, owners);
    // The merged runs replayed under the rule: done, or which configurations
    // lack runs it asks for (a shard not finished, or not merged).
    const ResultsContents contents = read_contents(Hdf5File::open_read_only(temporary));
    const AdaptiveState state =
        adaptive_state(contents, rule, static_cast<std::int32_t>(locations.size()),
                       static_cast<std::int32_t>(first.runs));
    if (!state.done) lacking = configurations_lacking_runs(state, locations);
    if (!lacking.empty() && !options.allow_partial) {
      throw UsageError(
          "the adaptive study is not done: its rule asks for runs of " + lacking +
          " that no shard holds (a shard not finished or not given): resume that shard with the "
          "command it was run with and --resume, then merge; or pass --allow-partial to merge "
          "what exists and then finish the study with `" +
          finish_command(first, options.program, output) + "`");
    }
  } catch (...) {
    std::filesystem::remove(temporary, error);
    throw;
  }
  std::filesystem::rename(temporary, output);
  std::size_t merged_runs = 0;
  for (const auto& owned : owners) merged_runs += owned.size();
  log << "ggk: merged " << merged_runs << " runs of an adaptive study from " << shards.size()
      << " shards into " << output.string() << "\n";
  if (!lacking.empty()) {
    log << "ggk: the study is not done: its rule asks for runs of " << lacking
        << "; finish it with `" << finish_command(first, options.program, output) << "`\n";
  }
}

}  // namespace

std::filesystem::path merging_path(const std::filesystem::path& output, pid_t pid) {
  return output.string() + ".merging-" + std::to_string(pid);
}

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
    shards.push_back(open_shard(path));
  }
  const ResultsHeader& first = shards.front().header;
  const std::string& task = first.task;
  const auto runs = static_cast<std::int32_t>(first.runs);
  check_one_job(shards, options);
  // Where the runs live: the task, or a study's configuration groups, the same
  // in every shard of one job.
  const std::vector<std::string> locations = runs_locations(shards.front().file, task);
  for (const Shard& shard : shards) {
    if (runs_locations(shard.file, task) != locations) {
      throw UsageError(shard.path.string() + " holds other run configurations than " +
                       shards.front().path.string() + ": only shards of one job merge");
    }
  }
  // Which shard holds each complete run of each location.
  const std::vector<std::map<std::int32_t, std::size_t>> owners =
      owners_of_runs(shards, locations, task, runs);
  if (const std::optional<AdaptiveRule> rule = adaptive_rule(first, shards.front().path)) {
    merge_adaptive_shards(output, shards, locations, owners, *rule, options, log);
    return;
  }
  // The runs complete in every location (a study's shards hold the same runs of
  // each configuration); a run missing anywhere is missing.
  std::map<std::int32_t, std::size_t> owner = owners.front();
  for (const auto& other : owners) {
    std::erase_if(owner, [&](const auto& entry) { return other.count(entry.first) == 0; });
  }
  std::size_t merged_runs = 0;
  for (const auto& other : owners) merged_runs += other.size();
  const Gaps missing = gaps(owner, runs);
  if (missing.count > 0 && !options.allow_partial) {
    throw UsageError(std::to_string(missing.count) + " of " + std::to_string(runs) +
                     " runs are complete in no shard: " + missing.text +
                     "; compute them (ggk run --runs A:B into another shard), or pass "
                     "--allow-partial to merge what exists and then compute them with `" +
                     finish_command(first, options.program, output) + "`");
  }

  verify_runs_to_merge(shards, locations, owners, task);

  // Written under a temporary name, renamed into place when whole.
  const std::filesystem::path temporary = merging_path(output, ::getpid());
  try {
    write_merged_file(temporary, shards, locations, owners);
  } catch (...) {
    std::filesystem::remove(temporary, error);
    throw;
  }
  std::filesystem::rename(temporary, output);
  log << "ggk: merged " << merged_runs << " of "
      << runs * static_cast<std::int64_t>(locations.size()) << " runs from " << shards.size()
      << " shards into " << output.string() << "\n";
  if (missing.count > 0) {
    log << "ggk: runs missing: " << missing.text << "; compute them with `"
        << finish_command(first, options.program, output) << "`\n";
  }
}

}  // namespace ggk::engine
