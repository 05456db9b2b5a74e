#include "engine/run/resume_compatibility.hpp"

#include <algorithm>
#include <cstdlib>
#include <map>
#include <optional>
#include <set>

#include "engine/job/job_compare.hpp"
#include "engine/job/job_input.hpp"
#include "engine/job/resolved_config.hpp"
#include "engine/job/sweep.hpp"
#include "engine/job/usage_error.hpp"
#include "engine/store/configuration_groups.hpp"
#include "engine/store/one_line.hpp"
#include "engine/store/results_layout.hpp"
#include "engine/store/results_rules.hpp"
#include "engine/store/run_store.hpp"

namespace ggk::engine {

namespace fs = std::filesystem;

namespace {

// The keys whose values a resumed job may add to: runs aside, the run-level
// study axes' (more run configurations) and the fit-level ones', built-in
// (sweep.basis ... sweep.lambda) or study axes (lspi.*: more fits of each run,
// store/run_extension.hpp).
struct GrowableKey {
  std::string key;
  bool fit_level = true;
};
std::vector<GrowableKey> growable_keys(const Study& study) {
  std::vector<GrowableKey> keys;
  for (const std::string_view axis : kSweepTableKeys)
    keys.push_back({"sweep." + std::string(axis)});
  for (const StudyAxis& axis : study.axes) {
    for (const std::string& key : axis.keys) {
      keys.push_back({key, axis.level == StageLevel::kFit});
    }
  }
  return keys;
}

// Whether the job (`wanted`: resolved_of(study)) grows the file's (more runs,
// more values of an axis: study.hpp), given that nothing else
// differs; a UsageError says what a job with fewer would drop.
bool grows(const ResolvedConfig& recorded, const ResolvedConfig& wanted, const Study& study,
           const fs::path& output) {
  bool grown = false;
  const auto number = [](const std::optional<std::string>& text) {
    return text ? std::strtoll(text->c_str(), nullptr, 10) : 0;
  };
  const long long had = number(recorded.value("runs")), has = number(wanted.value("runs"));
  if (has < had) {
    throw UsageError("cannot resume " + output.string() + ": it holds runs 0.." +
                     std::to_string(had - 1) + " and the job has " + std::to_string(has) +
                     ": resuming would drop runs " + std::to_string(has) + ".." +
                     std::to_string(had - 1) + "; resume with runs = " + std::to_string(had) +
                     " (--set runs=" + std::to_string(had) + "), or write to another -o");
  }
  grown = has > had;
  for (const auto& [key, fit_level] : growable_keys(study)) {
    {
      const auto before = canonical_elements(recorded.value(key).value_or(""));
      const auto after = canonical_elements(wanted.value(key).value_or(""));
      if (!before || !after) {
        throw UsageError("cannot resume " + output.string() + ": the study key " + key +
                         " is not an axis of the job in its results file");
      }
      std::string dropped;
      for (const std::string& value : *before) {
        if (std::find(after->begin(), after->end(), value) == after->end()) {
          dropped += (dropped.empty() ? "" : ", ") + value;
        }
      }
      if (!dropped.empty()) {
        throw UsageError("cannot resume " + output.string() + ": the job drops " + key + " = " +
                         dropped + ", whose " + (fit_level ? "fits" : "runs") +
                         " the results file holds (a study resumes "
                         "with the values it has, and may add more); add them back, or write "
                         "to another -o");
      }
      // Fits are numbered in the job's order: a run that gains no fit keeps its
      // numbers (a run-level axis's configuration groups are renumbered instead).
      if (fit_level && after->size() == before->size() && *after != *before) {
        throw UsageError("cannot resume " + output.string() + ": the job lists the values of " +
                         key + " in another order than its results file (" +
                         recorded.value(key).value_or("") + "), whose runs are numbered by it; " +
                         "list them in that order (new values may go anywhere)");
      }
      grown = grown || after->size() > before->size();
    }
  }
  return grown;
}

}  // namespace

// The file is the same job's (parsed job, input files), or one it grows into
// (returns true), or a UsageError says what differs.
bool check_same_job(const Hdf5File& file, const Study& study, const fs::path& output) {
  const JobSpec& job = study.job();
  ResultsHeader header;
  try {
    header = read_results_header(file);
  } catch (const ResultsHeaderError& e) {
    throw UsageError(
        "cannot resume " + output.string() + ": " + e.what() +
        "; choose another output with -o, or --overwrite to replace it (deleting what it "
        "holds)");
  }
  for (const std::string& mismatch :
       {layout_mismatch(header.layout), rules_mismatch(header.rules)}) {
    if (mismatch.empty()) continue;
    throw UsageError("cannot resume " + output.string() + ": " + mismatch +
                     "; write to another -o, or start it again with --overwrite (deleting its "
                     "complete runs)");
  }
  // The root's task names the group the runs are in (and what info, merge and diff
  // read): a file of another task (or a damaged name) is no file to resume.
  if (header.task != job.task) {
    throw UsageError("cannot resume " + output.string() + ": it holds " +
                     one_line(header.task, 60) + " results, not " + job.task +
                     " results; choose another output with -o, or --overwrite to replace it "
                     "(deleting what it holds)");
  }
  // Compared by meaning where the file records its resolved configuration (30
  // and 30.0, a key at its default and the key left out read alike); as TOML
  // where an older ggk wrote it. Where the results go is no part of them.
  std::optional<std::string> difference;
  bool grown = false;
  if (!header.job_resolved.empty()) {
    const std::optional<ResolvedConfig> recorded = ResolvedConfig::from_text(header.job_resolved);
    if (!recorded) {
      throw UsageError("cannot resume " + output.string() +
                       ": its job_resolved attribute is damaged (not a resolved configuration); "
                       "choose another output with -o, or --overwrite to replace it (deleting "
                       "its complete runs)");
    }
    // What may grow (runs, the values of study axes and the built-in ones) is
    // compared by grows().
    std::set<std::string> ignored = {"output.file", "output.compression", "runs"};
    for (const GrowableKey& growable : growable_keys(study)) ignored.insert(growable.key);
    const ResolvedConfig wanted = resolved_of(study);
    difference = recorded->difference(wanted, "the results file", "the job file", ignored);
    if (!difference) grown = grows(*recorded, wanted, study, output);
  } else {
    difference = job_difference(header.job, job.source_text);
  }
  if (difference) {
    throw UsageError("cannot resume " + output.string() + ": it holds the results of a different " +
                     "job (" + *difference + "; job file " + job.source_file.string() +
                     "); choose another output with -o, or --overwrite to replace it (deleting its "
                     "complete runs)");
  }
  for (const JobInput& input : job.inputs) {
    const auto recorded = std::find_if(header.inputs.begin(), header.inputs.end(),
                                       [&](const RecordedInput& r) { return r.key == input.key; });
    if (recorded == header.inputs.end() || recorded->text != input.text) {
      throw UsageError("cannot resume " + output.string() + ": " + input.path + " (" + input.key +
                       ") is not the file these results were computed from (it changed, "
                       "or the file predates ggk recording its inputs); restore it, or "
                       "write to another -o, or start over with --overwrite (deleting the runs it "
                       "holds)");
    }
  }
  return grown;
}

}  // namespace ggk::engine
