#include "engine/run/job_runner.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include "engine/job/sweep.hpp"
#include "engine/run/adaptive_runner.hpp"
#include "engine/run/fit_warnings.hpp"
#include "engine/run/job_writer.hpp"
#include "engine/run/memory_check.hpp"
#include "engine/run/open_results.hpp"
#include "engine/store/results_layout.hpp"
#include "engine/tasks/task_list.hpp"
#include "kernels/blas_runtime.hpp"

namespace ggk::engine {

RunRecord compute_run(const JobSpec& job, std::int32_t run) {
  const TaskDefinition* task = find_task(job.task);
  if (task == nullptr) throw std::logic_error("job names task '" + job.task + "', not registered");
  const std::vector<SweepPoint> points = expand_sweep(job);
  RunRecord record = task->compute_run(job, run, points);
  record.dataset_specs = task->datasets;
  return record;
}

RunRecord compute_unit(const Study& study, const WorkUnit& unit) {
  const RunConfiguration& configuration = study.configurations.at(unit.configuration);
  const TaskDefinition* task = find_task(configuration.job.task);
  if (task == nullptr) {
    throw std::logic_error("job names task '" + configuration.job.task + "', not registered");
  }
  std::vector<SweepPoint> points = expand_points(configuration);
  // An extension's lacking points (none: it renumbers the run's fits), or a
  // new run's needed ones.
  if (!unit.points.empty() || unit.extends) {
    std::vector<SweepPoint> chosen;
    for (const std::int32_t index : unit.points) chosen.push_back(points.at(index));
    points = std::move(chosen);
  }
  RunRecord record = task->compute_run(configuration.job, unit.run, points);
  record.dataset_specs = task->datasets;
  record.configuration = unit.configuration;
  record.extension = unit.extends;
  return record;
}

void check_study_memory(const Study& study, const RunOptions& options) {
  const JobSpec* largest = &study.job();
  double largest_bytes = 0.0;
  const auto variants = static_cast<std::int64_t>(study.configurations.front().variants.size());
  for (const RunConfiguration& configuration : study.configurations) {
    const double bytes = estimate_job_memory(configuration.job, 1, 1, variants).per_run;
    if (bytes > largest_bytes) {
      largest_bytes = bytes;
      largest = &configuration.job;
    }
  }
  RunOptions counted = options;
  if (study.configurations.size() > 1) {  // every configuration's runs are units at once
    const std::int64_t per_configuration =
        options.runs ? options.runs->last - options.runs->first : largest->runs;
    const std::int64_t units =
        per_configuration * static_cast<std::int64_t>(study.configurations.size());
    JobSpec widened = *largest;
    widened.runs = static_cast<std::int32_t>(std::min<std::int64_t>(units, INT32_MAX));
    counted.runs.reset();
    check_memory(widened, counted, variants);
    return;
  }
  check_memory(*largest, counted, variants);
}

std::int64_t failed_fits_of(const RunRecord& record) {
  std::int64_t failed = 0;
  for (const FitRecord& fit : record.fits) {
    if (is_failed_status(fit.status)) ++failed;
  }
  return failed;
}

ComputeThreads::ComputeThreads(std::int32_t threads) {
  if (threads > 0) {
    limit_ = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                   static_cast<std::size_t>(threads));
  }
  kernels::use_calling_thread_blas();  // before any task reaches the BLAS
  const kernels::BlasInfo blas = kernels::blas_info();
  if (!blas.concurrent_safe &&
      tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism) > 1) {
    throw UsageError("the BLAS is " + blas.name +
                     ", which is not safe to call from several threads at once; install "
                     "libopenblas0-pthread (scripts/install-deps.sh) or run with -j 1");
  }
}

void compute_units(const Study& study, std::span<const WorkUnit> units, JobWriter& writer,
                   RunTally& tally) {
  tbb::parallel_for(
      std::size_t{0}, units.size(),
      [&](std::size_t i) {
        const auto started = std::chrono::steady_clock::now();
        RunRecord computed = compute_unit(study, units[i]);
        computed.compute_seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
        auto record = std::make_shared<const RunRecord>(std::move(computed));
        tally.failed_fits.fetch_add(failed_fits_of(*record));
        tally.fits.fetch_add(static_cast<std::int64_t>(record->fits.size()));
        tally.warnings.add(*record);
        writer.commit(std::move(record));
      },
      tbb::simple_partitioner());
}

RunFailure stopped_job(JobWriter& writer, const std::runtime_error& error) {
  // The writer abandoned the file as its last commit left it, or writes the runs
  // queued before a run failed; or the output was never touched. Say which, and
  // how to go on.
  try {
    writer.wait();
  } catch (const std::runtime_error&) {  // the failure being reported, or its cause
  }
  const bool published = writer.target().temporary().empty();
  return RunFailure(std::string(error.what()) + "\nggk: " +
                    (published ? writer.go_on().published : writer.go_on().unpublished));
}

void print_notes(const std::vector<std::string>& notes) {
  for (const std::string& note : notes) std::fprintf(stderr, "ggk: %s\n", note.c_str());
}

void print_fit_warnings(const RunSummary& summary) {
  for (const std::string& line : summary.warnings) {
    std::fprintf(stderr, "ggk: warning: %s\n", line.c_str());
  }
}

void print_run_summary(const JobSpec& job, const RunSummary& s) {
  const std::string pieces = s.runs_in_pieces > 0 ? " (" + std::to_string(s.runs_in_pieces) +
                                                        " with their fits spread over ranks)"
                                                  : std::string();
  std::fprintf(stderr,
               "ggk: %s: %d runs computed%s, %d already complete, %lld fits (%lld failed) in "
               "%.1f s\nggk: results in %s\n",
               job.name.c_str(), s.runs_computed, pieces.c_str(), s.runs_skipped,
               static_cast<long long>(s.fits), static_cast<long long>(s.failed_fits), s.seconds,
               s.output.string().c_str());
  for (const std::string& line : s.adaptive) std::fprintf(stderr, "ggk: %s\n", line.c_str());
}

RunSummary run_job(const JobSpec& job, const RunOptions& options) {
  return run_study(study_of(job), options);
}

RunSummary run_study(const Study& study, const RunOptions& options) {
  if (study.job().adaptive) return run_adaptive_study(study, options);
  const auto started = std::chrono::steady_clock::now();
  const ComputeThreads threads(options.threads);
  check_study_memory(study, options);  // before the output is created or touched
  OpenedResults opened = open_results(study, options);
  print_notes(opened.notes);
  if (!options.quiet) print_notes(opened.info);
  RunSummary summary;
  summary.output = opened.target.output();
  summary.runs_skipped = opened.skipped;
  const std::vector<WorkUnit> pending = std::move(opened.pending);

  RunTally tally;
  JobWriter writer(study, options, std::move(opened), static_cast<std::int32_t>(pending.size()),
                   StopSignals::Mode::kStopInHandler);
  writer.expect_units(pending);
  try {
    compute_units(study, pending, writer, tally);
    writer.finish();
  } catch (const UsageError&) {
    throw;
  } catch (const std::runtime_error& e) {
    throw stopped_job(writer, e);
  }

  summary.runs_computed = static_cast<std::int32_t>(pending.size());
  summary.fits = tally.fits.load();
  summary.failed_fits = tally.failed_fits.load();
  summary.warnings = tally.warnings.lines();
  summary.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  return summary;
}

}  // namespace ggk::engine
