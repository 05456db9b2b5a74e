#include "engine/run/job_runner.hpp"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include "engine/job/sweep.hpp"
#include "engine/run/progress.hpp"
#include "engine/store/run_store.hpp"
#include "engine/store/store_writer.hpp"
#include "engine/tasks/task_list.hpp"
#include "kernels/blas_runtime.hpp"

#ifndef GGK_VERSION
#define GGK_VERSION "unknown"
#endif
#ifndef GGK_GIT_DESCRIBE
#define GGK_GIT_DESCRIBE "unknown"
#endif

namespace ggk::engine {

namespace {

std::string utc_now() {
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&now, &utc);
  char buffer[32];
  std::strftime(buffer, sizeof buffer, "%Y-%m-%dT%H:%M:%SZ", &utc);
  return buffer;
}

void check_output_directory(const std::filesystem::path& output) {
  const std::filesystem::path dir =
      output.parent_path().empty() ? std::filesystem::path(".") : output.parent_path();
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec)) {
    throw UsageError("output " + output.string() + ": directory " + dir.string() +
                     " does not exist");
  }
  if (access(dir.c_str(), W_OK) != 0) {
    throw UsageError("output " + output.string() + ": directory " + dir.string() +
                     " is not writable");
  }
  if (std::filesystem::is_directory(output, ec)) {
    throw UsageError("output " + output.string() + " is a directory");
  }
}

// The results file cannot be opened or created for reasons of the user's making
// (not an HDF5 file, no permission): a UsageError, reported like a bad -o.
template <class Open>
Hdf5File open_as_user(Open&& open) {
  try {
    return open();
  } catch (const UsageError&) {
    throw;
  } catch (const std::runtime_error& e) {
    throw UsageError(e.what());
  }
}

// Records which runs a shard file is for (root attribute runs_selected = [A, B]);
// a whole job's file has none. Rewritten on every open: a resumed file is for the
// selection it was last run with.
void mark_selection(Hdf5File& file, const JobSpec& job, const std::optional<RunRange>& runs) {
  if (file.has_attribute("/", "runs_selected")) file.remove_attribute("/", "runs_selected");
  if (runs && !(runs->first == 0 && runs->last == job.runs)) {
    const std::int64_t range[2] = {runs->first, runs->last};
    file.write_int64_array_attribute("/", "runs_selected", range);
  }
}

// Opens (resume) or creates the results file; returns the runs already complete.
Hdf5File open_or_create(const JobSpec& job, const RunOptions& options,
                        const std::filesystem::path& output, std::vector<std::int32_t>& complete) {
  const bool exists = std::filesystem::exists(output);
  if (exists && options.resume) {
    Hdf5File file = open_as_user([&] { return Hdf5File::open_read_write(output); });
    if (!file.has_attribute("/", "job") ||
        file.read_string_attribute("/", "job") != job.source_text) {
      throw UsageError("cannot resume " + output.string() +
                       ": it holds the results of a different job file (or none); choose "
                       "another output with -o, or --overwrite to replace it");
    }
    for (const JobInput& input : job.inputs) {
      const std::string attribute = input_attribute_name(input);
      if (!file.has_attribute("/", attribute) ||
          file.read_string_attribute("/", attribute) != input.text) {
        throw UsageError("cannot resume " + output.string() + ": " + input.path + " (" + input.key +
                         ") is not the file these results were computed from (it changed, "
                         "or the file predates ggk recording its inputs); restore it, or "
                         "start over with --overwrite or another -o");
      }
    }
    complete = prepare_for_resume(file, job);
    mark_selection(file, job, options.runs);
    file.flush();
    return file;
  }
  if (exists && !options.overwrite) {
    throw UsageError("output " + output.string() +
                     " exists: pass --resume to continue it or --overwrite to replace it");
  }
  Hdf5File file =
      open_as_user([&] { return Hdf5File::create(output, Hdf5File::CreateMode::kTruncate); });
  file.write_string_attribute("/", "job", job.source_text);
  file.write_string_attribute("/", "job_file", job.source_file.string());
  for (const JobInput& input : job.inputs) {
    file.write_string_attribute("/", input_attribute_name(input), input.text);
  }
  file.write_string_attribute("/", "ggk_version", GGK_VERSION);
  file.write_string_attribute("/", "git", GGK_GIT_DESCRIBE);
  file.write_string_attribute("/", "blas", kernels::blas_info().name);
  file.write_string_attribute("/", "created", utc_now());
  file.write_string_attribute("/", "task", job.task);
  file.write_int64_attribute("/", "runs", job.runs);
  file.create_group("/" + job.task);
  mark_selection(file, job, options.runs);
  file.flush();
  return file;
}

}  // namespace

RunRecord compute_run(const JobSpec& job, std::int32_t run) {
  const TaskDefinition* task = find_task(job.task);
  if (task == nullptr) throw std::logic_error("job names task '" + job.task + "', not registered");
  const std::vector<SweepPoint> points = expand_sweep(job);
  return task->compute_run(job, run, points);
}

std::int64_t failed_fits_of(const RunRecord& record) {
  std::int64_t failed = 0;
  for (const FitRecord& fit : record.fits) {
    if (fit.status == "invalid" || fit.status == "solver_failed") ++failed;
  }
  return failed;
}

OpenedResults open_results(const JobSpec& job, const RunOptions& options) {
  const std::filesystem::path output = options.output.empty() ? job.output.file : options.output;
  if (options.runs && (options.runs->first < 0 || options.runs->first >= options.runs->last ||
                       options.runs->last > job.runs)) {
    throw UsageError("--runs " + std::to_string(options.runs->first) + ":" +
                     std::to_string(options.runs->last) + " is not a range of runs of job '" +
                     job.name + "', which has runs 0.." + std::to_string(job.runs - 1) +
                     " (A:B computes runs A..B-1, 0 <= A < B <= " + std::to_string(job.runs) + ")");
  }
  check_output_directory(output);
  std::vector<std::int32_t> complete;
  OpenedResults opened{open_or_create(job, options, output, complete), output, {}, 0};
  opened.file.set_gzip_level(job.output.compression);
  const std::int32_t first = options.runs ? options.runs->first : 0;
  const std::int32_t last = options.runs ? options.runs->last : job.runs;
  for (std::int32_t run = first; run < last; ++run) {
    if (std::binary_search(complete.begin(), complete.end(), run)) {
      ++opened.skipped;
    } else {
      opened.pending.push_back(run);
    }
  }
  return opened;
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

void print_run_summary(const JobSpec& job, const RunSummary& s) {
  std::fprintf(stderr,
               "ggk: %s: %d runs computed, %d already complete, %lld fits (%lld failed) in "
               "%.1f s\nggk: results in %s\n",
               job.name.c_str(), s.runs_computed, s.runs_skipped, static_cast<long long>(s.fits),
               static_cast<long long>(s.failed_fits), s.seconds, s.output.string().c_str());
}

RunSummary run_job(const JobSpec& job, const RunOptions& options) {
  const auto started = std::chrono::steady_clock::now();
  const ComputeThreads threads(options.threads);
  OpenedResults opened = open_results(job, options);
  RunSummary summary;
  summary.output = opened.output;
  summary.runs_skipped = opened.skipped;
  const std::vector<std::int32_t>& pending = opened.pending;
  const auto fits_per_run = static_cast<std::int32_t>(expand_sweep(job).size());

  StoreWriter writer(std::move(opened.file));
  std::atomic<std::int64_t> failed_fits{0};
  {
    Progress progress(static_cast<std::int32_t>(pending.size()), fits_per_run, options.quiet);
    tbb::parallel_for(
        std::size_t{0}, pending.size(),
        [&](std::size_t i) {
          auto record = std::make_shared<const RunRecord>(compute_run(job, pending[i]));
          failed_fits.fetch_add(failed_fits_of(*record));
          writer.submit([record, &job, &progress](Hdf5File& f) {
            write_run(f, job, *record);
            progress.run_done();
          });
        },
        tbb::simple_partitioner());
    writer.wait();
  }
  writer.submit([&job](Hdf5File& f) { write_summary(f, job); });
  writer.close();

  summary.runs_computed = static_cast<std::int32_t>(pending.size());
  summary.fits = static_cast<std::int64_t>(pending.size()) * fits_per_run;
  summary.failed_fits = failed_fits.load();
  summary.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  return summary;
}

}  // namespace ggk::engine
