#include "engine/cli/validate_command.hpp"

#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <system_error>

#include "engine/hdf5/hdf5_file.hpp"
#include "engine/job/job_file.hpp"
#include "engine/job/study.hpp"
#include "engine/job/usage_error.hpp"
#include "engine/run/adaptive_runner.hpp"
#include "engine/run/adaptive_shards.hpp"
#include "engine/run/isolated_reading.hpp"
#include "engine/run/memory_check.hpp"
#include "engine/run/resume_preview.hpp"
#include "engine/store/output_lock.hpp"
#include "engine/tasks/task_list.hpp"

namespace ggk::engine {

namespace {

// The output validate was given exists: what `ggk run` would do with it, in a
// child (the file is not ggk's to trust: isolated_reading.hpp). With --resume a
// refusal is validate's too (exit 2); without, a note.
void preview_existing_output(const Study& study, const std::filesystem::path& output,
                             const RunOptions& run_options, bool quiet) {
  if (run_options.overwrite) {
    if (!quiet)
      std::printf("%s exists: ggk run --overwrite would replace it (deleting its runs)\n",
                  output.c_str());
    return;
  }
  if (!run_options.resume && !quiet) {
    std::printf(
        "%s exists: ggk run refuses it unless --resume (continue it) or --overwrite "
        "(replace it, deleting its runs)\n",
        output.c_str());
  }
  if (const auto writer = OutputLock::writer_of(output)) {
    if (run_options.resume) {
      throw UsageError(output.string() + " is being written by " + *writer +
                       ": ggk run --resume waits for nothing and would be refused");
    }
    if (!quiet) std::printf("%s is being written by %s\n", output.c_str(), writer->c_str());
    return;
  }
  try {
    read_isolated({output}, [&] {
      const Hdf5File file = Hdf5File::open_read_only(output);
      const ResumePreview preview = preview_resume(file, study, output);
      if (!quiet) {
        for (const std::string& line : preview_words(preview, study, run_options.threads)) {
          std::printf("%s\n", line.c_str());
        }
      }
      std::fflush(stdout);
      return 0;
    });
  } catch (const UsageError& e) {
    if (run_options.resume) throw;
    if (!quiet) std::printf("ggk run --resume would refuse it: %s\n", e.what());
  } catch (const std::runtime_error& e) {  // does not open: run --resume salvages it
    if (run_options.resume) {
      if (!quiet)
        std::printf(
            "%s does not read whole (%s): ggk run --resume would salvage its whole "
            "runs into a new file\n",
            output.c_str(), e.what());
      return;
    }
    if (!quiet) std::printf("it does not read whole: %s\n", e.what());
  }
}

int validate_job(const std::string& job_path, const std::string& output, JobLoadOptions load,
                 const RunOptions& run_options, bool quiet, bool print_job) {
  // Checks what `ggk run` with the same arguments would: the job file, the
  // overrides, the output (-o, else the job's, relative to this directory) and
  // the memory the job needs at -j (run's refusal, the same message and exit 2;
  // --ignore-memory-check skips it as it does for run). A study (study.hpp) has
  // every point checked, and its stages listed.
  if (!output.empty()) load.output_file = output;
  if (print_job) load.check_output = false;  // printing the job writes nothing
  const Study study = load_study(job_path, task_tables(), load);
  check_adaptive_metrics(study);
  check_study_memory(study, run_options);
  const JobSpec& job = study.job();
  // The largest configuration's run (a study's configurations differ in size).
  JobMemoryEstimate memory = estimate_job_memory(job, 1, 1);
  std::size_t fits = 0;
  for (const RunConfiguration& configuration : study.configurations) {
    fits += expand_points(configuration).size();
    const JobMemoryEstimate estimate = estimate_job_memory(
        configuration.job, 1, 1, static_cast<std::int64_t>(configuration.variants.size()));
    if (estimate.per_run > memory.per_run) memory = estimate;
  }
  if (print_job) {
    std::fputs(resolved_job_toml(study).c_str(), stdout);
    return 0;
  }
  const std::filesystem::path written =
      output.empty() ? job.output.file : std::filesystem::path(output);
  std::error_code error;
  const bool exists = std::filesystem::is_regular_file(written, error) &&
                      std::filesystem::file_size(written, error) > 0;
  if (!exists && run_options.resume && !quiet) {
    std::printf("%s does not exist yet: ggk run --resume would start it\n", written.c_str());
  }
  if (quiet) {
    if (exists) preview_existing_output(study, written, run_options, quiet);
    return 0;
  }
  if (job.adaptive) {
    std::printf("%s\n", adaptive_rule_words(*job.adaptive, job.runs).c_str());
    const AdaptivePlan plan = adaptive_plan_of(study);
    std::printf(
        "adaptive: %lld cells over %zu run configurations, in %d groups no cell links: in "
        "shards, --shard I/N with N up to %d (shards split it by configurations)\n",
        static_cast<long long>(plan.cells), study.configurations.size(), plan.groups, plan.groups);
  }
  if (!study.has_axes()) {
    std::printf("%s: ok (task %s, %d runs x %zu sweep points); about %s of memory per run\n",
                job_path.c_str(), job.task.c_str(), job.runs, fits,
                format_bytes(memory.per_run).c_str());
    if (exists) preview_existing_output(study, written, run_options, quiet);
    return 0;
  }
  std::printf(
      "%s: ok, a study (task %s, %zu run configurations x %d runs, %zu fits per run "
      "of every configuration together); about %s of memory per run of the largest "
      "configuration\n",
      job_path.c_str(), job.task.c_str(), study.configurations.size(), job.runs, fits,
      format_bytes(memory.per_run).c_str());
  for (const StudyAxis& axis : study.axes) {
    std::string keys, values;
    for (const std::string& key : axis.keys) keys += (keys.empty() ? "" : " + ") + key;
    for (const auto& value : axis.values) {
      std::string tuple;
      for (const std::string& part : value) tuple += (tuple.empty() ? "" : "/") + part;
      values += (values.empty() ? "" : ", ") + tuple;
    }
    std::printf("  axis %s = [%s]: %s\n", keys.c_str(), values.c_str(),
                axis.level == StageLevel::kRun ? "run-level (each value its own samples and graph)"
                                               : "fit-level (more fits of the same runs)");
  }
  if (exists) preview_existing_output(study, written, run_options, quiet);
  return 0;
}

}  // namespace

int validate_command(const CommandLine& line) {
  if (line.options.resume && line.options.overwrite) {
    throw UsageError("--resume and --overwrite exclude each other");
  }
  JobLoadOptions load;
  load.overrides = line.overrides;
  load.sweeps = line.sweeps;
  return validate_job(line.job_path, line.output, load, line.options, line.quiet, line.print_job);
}

}  // namespace ggk::engine
