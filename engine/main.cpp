// ggk: the command line. Turns user errors (bad job files, outputs, options) into
// one clear message on stderr and exit status 2; results go only to HDF5 files.

#include <omp.h>

#include <cstdio>
#include <filesystem>
#include <iostream>
#include <string>

#include <CLI/CLI.hpp>

#include "engine/job/job_error.hpp"
#include "engine/job/job_file.hpp"
#include "engine/job/sweep.hpp"
#include "engine/run/job_runner.hpp"
#include "engine/store/results_info.hpp"
#include "engine/tasks/task_list.hpp"

namespace {

constexpr int kUserError = 2;

int run_command(const std::string& job_path, const ggk::engine::RunOptions& options) {
  ggk::engine::JobLoadOptions load;
  load.check_output = options.output.empty();  // -o replaces the job's output
  const ggk::engine::JobSpec job =
      ggk::engine::load_job_file(job_path, ggk::engine::task_tables(), load);
  const ggk::engine::RunSummary s = ggk::engine::run_job(job, options);
  std::fprintf(stderr,
               "ggk: %s: %d runs computed, %d already complete, %lld fits (%lld failed) in "
               "%.1f s\nggk: results in %s\n",
               job.name.c_str(), s.runs_computed, s.runs_skipped, static_cast<long long>(s.fits),
               static_cast<long long>(s.failed_fits), s.seconds, s.output.string().c_str());
  return 0;
}

int validate_command(const std::string& job_path) {
  const ggk::engine::JobSpec job = ggk::engine::load_job_file(job_path, ggk::engine::task_tables());
  std::printf("%s: ok (task %s, %d runs x %zu sweep points)\n", job_path.c_str(), job.task.c_str(),
              job.runs, ggk::engine::expand_sweep(job).size());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  // Parallelism belongs to oneTBB: no OpenMP teams inside SuiteSparse calls.
  omp_set_num_threads(1);

  CLI::App app{"ggk: least-squares policy iteration with geodesic Gaussian kernels"};
  app.require_subcommand(1);

  std::string job_path, info_path;
  ggk::engine::RunOptions options;
  std::string output;
  CLI::App* run = app.add_subcommand("run", "Run a sweep job file, writing one HDF5 file");
  run->add_option("job", job_path, "job file (TOML)")->required();
  run->add_option("-j,--threads", options.threads, "worker threads (default: all cores)")
      ->check(CLI::Range(1, 4096));
  run->add_option("-o,--output", output, "results file (default: the job's [output] file)");
  run->add_flag("--resume", options.resume, "continue an interrupted run of the same job");
  run->add_flag("--overwrite", options.overwrite, "replace an existing results file");
  run->add_flag("-q,--quiet", options.quiet, "no progress output");

  CLI::App* validate = app.add_subcommand("validate", "Check a job file and exit");
  validate->add_option("job", job_path, "job file (TOML)")->required();

  CLI::App* info = app.add_subcommand("info", "Describe a results file");
  info->add_option("file", info_path, "results file (HDF5)")->required();

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int status = app.exit(e);
    return status == 0 ? 0 : kUserError;
  }

  try {
    if (*run) {
      if (options.resume && options.overwrite) {
        throw ggk::engine::UsageError("--resume and --overwrite exclude each other");
      }
      options.output = output;
      return run_command(job_path, options);
    }
    if (*validate) return validate_command(job_path);
    if (*info) {
      ggk::engine::print_results_info(info_path, std::cout);
      return 0;
    }
  } catch (const ggk::engine::JobError& e) {
    std::fprintf(stderr, "ggk: error: %s\n", e.what());
    return kUserError;
  } catch (const ggk::engine::UsageError& e) {
    std::fprintf(stderr, "ggk: error: %s\n", e.what());
    return kUserError;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ggk: internal error: %s\n", e.what());
    return 1;
  }
  return 0;
}
