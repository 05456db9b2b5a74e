// ggk: the command line. Turns user errors (bad job files, outputs, options) into
// one clear message on stderr and exit status 2; results go only to HDF5 files.
// Under an MPI launcher (mpirun, srun) `ggk run` spreads the runs over the ranks
// (engine/run/mpi_runner.hpp); everything else runs on rank 0 alone.

#include <omp.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <CLI/CLI.hpp>

#include "engine/job/job_error.hpp"
#include "engine/job/job_file.hpp"
#include "engine/job/resolved_config.hpp"
#include "engine/job/shell_words.hpp"
#include "engine/job/spelling.hpp"
#include "engine/job/study.hpp"
#include "engine/job/sweep.hpp"
#include "engine/job/usage_error.hpp"
#include "engine/run/adaptive_runner.hpp"
#include "engine/run/address_space.hpp"
#include "engine/run/cpu_affinity.hpp"
#include "engine/run/isolated_merge.hpp"
#include "engine/run/isolated_reading.hpp"
#include "engine/run/job_runner.hpp"
#include "engine/run/memory_check.hpp"
#include "engine/run/open_results.hpp"
#include "engine/run/resume_preview.hpp"
#include "engine/run/shards.hpp"
#include "engine/store/output_lock.hpp"
#include "engine/store/results_diff.hpp"
#include "engine/store/results_info.hpp"
#include "engine/store/results_merge.hpp"
#include "engine/store/results_verify.hpp"
#include "engine/tasks/task_list.hpp"
#if GGK_WITH_PYTHON
#include "engine/tasks/python_env/python_runtime.hpp"
#endif
#if GGK_WITH_MPI
#include "engine/run/mpi_runner.hpp"
#endif

namespace {

namespace engine = ggk::engine;
constexpr int kUserError = 2;

int run_command(const std::string& job_path, const engine::RunOptions& options,
                const engine::JobLoadOptions& load) {
  const engine::Study study = engine::load_study(job_path, engine::task_tables(), load);
  const engine::RunSummary summary = engine::run_study(study, options);
  engine::print_fit_warnings(summary);
  if (!options.quiet) engine::print_run_summary(study.job(), summary);
  return 0;
}

// The output validate was given exists: what `ggk run` would do with it, in a
// child (the file is not ggk's to trust: isolated_reading.hpp). With --resume a
// refusal is validate's too (exit 2); without, a note.
void preview_existing_output(const engine::Study& study, const std::filesystem::path& output,
                             const engine::RunOptions& run_options, bool quiet) {
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
  if (const auto writer = engine::OutputLock::writer_of(output)) {
    if (run_options.resume) {
      throw engine::UsageError(output.string() + " is being written by " + *writer +
                               ": ggk run --resume waits for nothing and would be refused");
    }
    if (!quiet) std::printf("%s is being written by %s\n", output.c_str(), writer->c_str());
    return;
  }
  try {
    engine::read_isolated({output}, [&] {
      const engine::Hdf5File file = engine::Hdf5File::open_read_only(output);
      const engine::ResumePreview preview = engine::preview_resume(file, study, output);
      if (!quiet) {
        for (const std::string& line : engine::preview_words(preview, study, run_options.threads)) {
          std::printf("%s\n", line.c_str());
        }
      }
      std::fflush(stdout);
      return 0;
    });
  } catch (const engine::UsageError& e) {
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

int validate_command(const std::string& job_path, const std::string& output,
                     engine::JobLoadOptions load, const engine::RunOptions& run_options, bool quiet,
                     bool print_job) {
  // Checks what `ggk run` with the same arguments would: the job file, the
  // overrides, the output (-o, else the job's, relative to this directory) and
  // the memory the job needs at -j (run's refusal, the same message and exit 2;
  // --ignore-memory-check skips it as it does for run). A study (study.hpp) has
  // every point checked, and its stages listed.
  if (!output.empty()) load.output_file = output;
  if (print_job) load.check_output = false;  // printing the job writes nothing
  const engine::Study study = engine::load_study(job_path, engine::task_tables(), load);
  engine::check_adaptive_metrics(study);
  engine::check_study_memory(study, run_options);
  const engine::JobSpec& job = study.job();
  // The largest configuration's run (a study's configurations differ in size).
  engine::JobMemoryEstimate memory = engine::estimate_job_memory(job, 1, 1);
  std::size_t fits = 0;
  for (const engine::RunConfiguration& configuration : study.configurations) {
    fits += engine::expand_points(configuration).size();
    const engine::JobMemoryEstimate estimate = engine::estimate_job_memory(
        configuration.job, 1, 1, static_cast<std::int64_t>(configuration.variants.size()));
    if (estimate.per_run > memory.per_run) memory = estimate;
  }
  if (print_job) {
    std::fputs(engine::resolved_job_toml(study).c_str(), stdout);
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
  if (job.adaptive)
    std::printf("%s\n", engine::adaptive_rule_words(*job.adaptive, job.runs).c_str());
  if (!study.has_axes()) {
    std::printf("%s: ok (task %s, %d runs x %zu sweep points); about %s of memory per run\n",
                job_path.c_str(), job.task.c_str(), job.runs, fits,
                engine::format_bytes(memory.per_run).c_str());
    if (exists) preview_existing_output(study, written, run_options, quiet);
    return 0;
  }
  std::printf(
      "%s: ok, a study (task %s, %zu run configurations x %d runs, %zu fits per run "
      "of every configuration together); about %s of memory per run of the largest "
      "configuration\n",
      job_path.c_str(), job.task.c_str(), study.configurations.size(), job.runs, fits,
      engine::format_bytes(memory.per_run).c_str());
  for (const engine::StudyAxis& axis : study.axes) {
    std::string keys, values;
    for (const std::string& key : axis.keys) keys += (keys.empty() ? "" : " + ") + key;
    for (const auto& value : axis.values) {
      std::string tuple;
      for (const std::string& part : value) tuple += (tuple.empty() ? "" : "/") + part;
      values += (values.empty() ? "" : ", ") + tuple;
    }
    std::printf("  axis %s = [%s]: %s\n", keys.c_str(), values.c_str(),
                axis.level == engine::StageLevel::kRun
                    ? "run-level (each value its own samples and graph)"
                    : "fit-level (more fits of the same runs)");
  }
  if (exists) preview_existing_output(study, written, run_options, quiet);
  return 0;
}

// A run with --set or --sweep computes something other than its job file: its
// results never take the file's output name (where the plain job's results
// live) unless an override names the output. Refused (exit 2) with how to name it.
void require_own_output(const std::vector<std::string>& overrides,
                        const std::vector<std::string>& sweeps, const std::string& output) {
  if (!output.empty() || (overrides.empty() && sweeps.empty())) return;
  for (const std::string& text : overrides) {
    std::string key = text.substr(0, text.find('='));
    key.erase(0, key.find_first_not_of(" \t"));
    key.erase(key.find_last_not_of(" \t") + 1);
    if (key == "output" || key == "output.file") return;
  }
  throw engine::UsageError(
      std::string(overrides.empty() ? "--sweep" : "--set") +
      " makes another job than the job file, whose [output] file holds (or will hold) the plain "
      "job's results: name this one's results file with -o FILE.h5 (or --set output.file=...)");
}

// "A:B" -> runs A..B-1; the range is checked against the job when it runs.
engine::RunRange parse_run_range(const std::string& text) {
  const std::size_t colon = text.find(':');
  try {
    if (colon == std::string::npos) throw std::invalid_argument("no colon");
    std::size_t used_first = 0, used_last = 0;
    const int first = std::stoi(text.substr(0, colon), &used_first);
    const int last = std::stoi(text.substr(colon + 1), &used_last);
    if (used_first != colon || used_last != text.size() - colon - 1) {
      throw std::invalid_argument("trailing characters");
    }
    return {first, last};
  } catch (const std::exception&) {
    throw engine::UsageError("--runs " + text +
                             ": expected A:B, the runs A..B-1 (e.g. --runs 0:10)");
  }
}

// --sweep, the same for run and validate.
void add_sweep_option(CLI::App& command, std::vector<std::string>& sweeps) {
  command
      .add_option("--sweep", sweeps,
                  "KEY=V1,V2,...: make a job key a study axis over these values (e.g. --sweep "
                  "khepera.motion.turn_deg=15,30,45; --sweep kernels=10,20 replaces an axis); "
                  "jobs/README.md, Studies")
      ->expected(1)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
}

// --set, the same for run and validate.
void add_set_option(CLI::App& command, std::vector<std::string>& overrides) {
  command
      .add_option("--set", overrides,
                  "KEY=VALUE: override a job key (e.g. --set runs=5 --set "
                  "khepera.motion.turn_deg=30); validated like the file, recorded in the results")
      ->expected(1)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
}

// "Did you mean": CLI11 says only that an argument was not expected. Looks at
// the command line before CLI11 does: an unknown command, or an option the
// command does not have, is a UsageError naming the closest spelling.
void check_spelling(const CLI::App& app, int argc, char** argv) {
  if (argc < 2) return;
  const std::string first = argv[1];
  std::vector<std::string> names;
  const CLI::App* command = nullptr;
  for (const CLI::App* sub : app.get_subcommands({})) {
    names.push_back(sub->get_name());
    if (sub->get_name() == first) command = sub;
  }
  const auto suggestion = [](const std::string& word, const std::vector<std::string>& candidates) {
    const std::vector<std::string_view> views(candidates.begin(), candidates.end());
    const auto closest = engine::closest_spelling(word, views);
    return closest ? " (did you mean '" + std::string(*closest) + "'?)" : std::string();
  };
  if (first.empty() || first[0] != '-') {
    if (command == nullptr) {
      std::string list;
      for (const std::string& name : names) list += (list.empty() ? "" : ", ") + name;
      throw engine::UsageError("unknown command '" + first + "'" + suggestion(first, names) +
                               "; the commands: " + list + " (ggk --help)");
    }
  } else {
    return;  // --help, --version: CLI11's
  }
  std::vector<std::string> options;
  std::vector<const CLI::Option*> takes_value;
  for (const CLI::Option* option : command->get_options()) {
    for (const std::string& name : option->get_lnames()) options.push_back("--" + name);
    for (const std::string& name : option->get_snames()) options.push_back("-" + name);
  }
  const bool takes_job = first == "run" || first == "validate";
  int positionals = 0;
  for (int i = 2; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--") return;
    if (arg.empty() || arg[0] != '-') {
      // Hydra's habit: a bare KEY=VALUE after the job, where ggk takes --set / --sweep.
      if (takes_job && ++positionals > 1 && arg.find('=') != std::string::npos) {
        const std::string key = arg.substr(0, arg.find('='));
        throw engine::UsageError("'" + arg + "': ggk takes no bare KEY=VALUE; write --set " + arg +
                                 " to override " + key + ", or --sweep " + arg +
                                 " to make it a study axis");
      }
      continue;
    }
    if (arg.size() < 2 || (arg[1] >= '0' && arg[1] <= '9')) continue;
    const std::string name = arg.substr(0, arg.find('='));
    const bool is_long = arg.rfind("--", 0) == 0;
    const std::string key = is_long ? name : arg.substr(0, 2);
    const CLI::Option* option = command->get_option_no_throw(key);
    if (option == nullptr) {
      throw engine::UsageError("unknown option '" + name + "' for 'ggk " + first + "'" +
                               suggestion(name, options) + " (ggk " + first + " --help)");
    }
    // Skip the option's value, which may start with '-'.
    if (option->get_items_expected_min() > 0 && arg.find('=') == std::string::npos &&
        (is_long || arg.size() == 2)) {
      ++i;
    }
  }
}

}  // namespace

namespace {

// `ggk verify` of a file that `writer` (OutputLock::writer_of) writes now: the
// report goes to a scratch file first (the verifying child prints it there) and
// reaches `out` only when the file is whole; anything else is "being written".
int verify_while_written(const std::string& path, const std::string& writer, std::ostream& out) {
  std::string scratch = (std::filesystem::temp_directory_path() / "ggk-verify-XXXXXX").string();
  const int fd = ::mkstemp(scratch.data());
  if (fd < 0)
    throw ggk::engine::UsageError("cannot create a scratch file in " +
                                  std::filesystem::temp_directory_path().string());
  ::close(fd);
  int status = 1;
  try {
    status = ggk::engine::read_isolated({path}, [&] {
      std::ofstream report(scratch);
      return ggk::engine::verify_results(path, report) ? 0 : 1;
    });
  } catch (const ggk::engine::ReadingCrash&) {
  } catch (const ggk::engine::UsageError&) {
  }
  if (status == 0) {
    std::ifstream report(scratch);
    out << report.rdbuf();
  }
  ::unlink(scratch.c_str());
  if (status == 0) return 0;
  std::cerr << "ggk: " << path << " is being written by " << writer
            << ": it cannot be verified between its writes; run `ggk verify "
            << ggk::engine::shell_quoted(path) << "` again when that ggk has finished or stopped\n";
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  // Under ulimit -v, OpenBLAS's thread pool can spin forever: restart without it.
  engine::restart_without_blas_pool(argv);
  // Parallelism belongs to oneTBB: no OpenMP teams inside SuiteSparse calls.
  omp_set_num_threads(1);
  // As typed (before an MPI launcher's library may edit argv): the commands
  // ggk prints to resume repeat it.
  const std::vector<std::string> invocation(argv, argv + argc);

#if GGK_WITH_MPI
  std::optional<engine::MpiSession> mpi;
  if (engine::launched_by_mpi()) mpi.emplace(argc, argv);
  const bool quiet_rank = mpi && mpi->rank() != 0;
#else
  const bool quiet_rank = false;
#endif

  CLI::App app{"ggk: least-squares policy iteration with geodesic Gaussian kernels"};
  app.require_subcommand(1);
#if GGK_WITH_PYTHON
  const std::string embedded = "; python_env embeds " + engine::python::embedded_version();
#else
  const std::string embedded = "; built without Python (no python_env task)";
#endif
  app.set_version_flag("--version", "ggk " + engine::ggk_version_text() + embedded);

  std::string job_path, info_path, runs_text, shard_text;
  engine::RunOptions options;
  std::string output;
  std::vector<std::string> overrides, sweeps;
  double rank_timeout = 60.0;
  CLI::App* run = app.add_subcommand("run", "Run a sweep job file, writing one HDF5 file");
  run->add_option("job", job_path, "job file (TOML)")->required();
  run->add_option("-j,--threads", options.threads, "worker threads (default: all cores)")
      ->check(CLI::Range(1, 4096));
  run->add_option("-o,--output", output, "results file, *.h5 (default: the job's [output] file)");
  add_set_option(*run, overrides);
  add_sweep_option(*run, sweeps);
  run->add_flag("--resume", options.resume, "continue an interrupted run of the same job");
  run->add_flag("--overwrite", options.overwrite, "replace an existing results file");
  run->add_flag("-q,--quiet", options.quiet,
                "print nothing but errors and warnings (no progress, no final summary)");
  run->add_flag("--ignore-memory-check", options.ignore_memory_check,
                "run even when the job's estimated memory exceeds what is available");
  run->add_option("--runs", runs_text,
                  "A:B computes only runs A..B-1 (a shard for a job array; join with ggk merge)");
  run->add_option("--shard", shard_text,
                  "I/N computes shard I of N (0 <= I < N; contiguous, balanced runs) into "
                  "OUT.shard-I-of-N.h5; 'slurm': I and N from a job array (sbatch --array=0-3); "
                  "join with ggk merge --shards-of JOB");
  run->add_option("--rank-timeout", rank_timeout,
                  "under MPI: seconds a rank may stay silent before the job stops (default 60)")
      ->check(CLI::PositiveNumber);

  CLI::App* validate = app.add_subcommand("validate", "Check a job file and exit");
  validate->add_option("job", job_path, "job file (TOML)")->required();
  validate->add_option("-o,--output", output, "the results file `ggk run -o` would write");
  validate
      ->add_option("-j,--threads", options.threads,
                   "worker threads `ggk run -j` would use, for its memory check (default: all "
                   "cores)")
      ->check(CLI::Range(1, 4096));
  validate->add_flag("--ignore-memory-check", options.ignore_memory_check,
                     "accept a job whose estimated memory exceeds what is available");
  add_set_option(*validate, overrides);
  add_sweep_option(*validate, sweeps);
  validate->add_flag("--resume", options.resume,
                     "as run --resume: an existing output must be this job's (else exit 2); "
                     "prints what the resume would compute");
  validate->add_flag("--overwrite", options.overwrite, "as run --overwrite");
  bool print_job = false;
  validate->add_flag("--print", print_job,
                     "print the resolved job as TOML (every key, defaults filled in) and exit");
  // -q on every command: nothing on standard output, no progress or summary on
  // standard error; errors and warnings (a damaged run redone) still print.
  bool quiet = false;
  validate->add_flag("-q,--quiet", quiet, "print nothing but errors");

  engine::InfoOptions info_options;
  bool info_csv = false;
  std::string info_columns, info_paired;
  CLI::App* info = app.add_subcommand("info", "Describe a results file");
  info->add_option("file", info_path, "results file (HDF5)")->required();
  info->add_flag("--csv", info_csv,
                 "print the per-sweep-point summary as CSV (means and 95 % CI bounds)");
  info->add_option("--columns", info_columns,
                   "a,b,c: show these metrics only (default: all), in this order");
  info->add_option("--paired", info_paired,
                   "AXIS=A,B: per point of the other axes, the mean difference A - B of each "
                   "metric paired by run, with its 95 % CI (e.g. basis=ggk,ogk)");
  info->add_flag("--adaptive", info_options.adaptive,
                 "an adaptive study's cells only: each comparison's state (+, -, narrow, open, "
                 "capped), runs, mean difference and confidence-sequence bounds (with --csv: CSV)");
  info->add_flag("-q,--quiet", quiet, "print nothing but errors");

  std::string verify_path;
  CLI::App* verify = app.add_subcommand(
      "verify", "Read every dataset of a results file back: exit 0 when whole, 1 when damaged");
  verify->add_option("file", verify_path, "results file (HDF5)")->required();
  verify->add_flag("-q,--quiet", quiet, "print nothing but errors: the exit status says it");

  std::vector<std::string> diff_files;
  CLI::App* diff = app.add_subcommand(
      "diff", "Exit 0 when two results files hold the same results, 1 (naming them) when not");
  diff->add_option("files", diff_files, "two results files")->required()->expected(2);
  engine::DiffOptions diff_options;
  diff->add_option("--rtol", diff_options.tolerance.rtol,
                   "floats equal when |a - b| <= atol + rtol |b| (default 0: bit for bit); "
                   "exit 0 same, 1 different, 2 usage error");
  diff->add_option("--atol", diff_options.tolerance.atol,
                   "absolute tolerance of floats (default 0)");
  diff->add_option("--exclude", diff_options.exclude,
                   "GLOB: leave out objects whose printed path matches (repeatable), e.g. "
                   "'*/history/*'");
  diff->add_flag("--common", diff_options.common,
                 "compare what both files hold: a configuration, run, fit or summary row only "
                 "one holds (a study with more values) is a note, not a difference");
  diff->add_flag("-q,--quiet", quiet, "print nothing but errors: the exit status says it");

  std::string merge_output, merge_job;
  std::vector<std::string> merge_inputs;
  engine::MergeOptions merge_options;
  CLI::App* merge = app.add_subcommand(
      "merge",
      "Join shards of one job (ggk run --shard I/N or --runs A:B) into the file the "
      "whole job writes");
  merge->add_option("output", merge_output,
                    "the merged results file (must not exist; with --shards-of, default: the "
                    "job's output)");
  merge->add_option("shards", merge_inputs, "shard results files")->expected(0, -1);
  merge->add_option("--shards-of", merge_job,
                    "JOB: merge the shards of OUT (the job's output) that ggk run JOB --shard "
                    "wrote, OUT.shard-I-of-N.h5, refusing when one is missing");
  std::string merge_output_option;
  std::vector<std::string> merge_overrides, merge_sweeps;
  merge->add_option("-o,--output", merge_output_option,
                    "OUT: the merged results file, as ggk run's -o (then every positional "
                    "argument is a shard)");
  merge
      ->add_option("--set", merge_overrides,
                   "KEY=VALUE: with --shards-of, the --set options the shards were run with")
      ->expected(1)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  merge
      ->add_option("--sweep", merge_sweeps,
                   "KEY=V1,V2,...: with --shards-of, the --sweep options the shards were run "
                   "with")
      ->expected(1)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  merge->add_flag("--allow-partial", merge_options.allow_partial,
                  "merge even when runs are missing (ggk run --resume computes them)");
  merge->add_flag("-q,--quiet", quiet, "print nothing but errors");

  try {
    check_spelling(app, argc, argv);
  } catch (const engine::UsageError& e) {
    if (!quiet_rank) std::fprintf(stderr, "ggk: error: %s\n", e.what());
    return kUserError;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int status = quiet_rank ? (e.get_exit_code() == 0 ? 0 : kUserError) : app.exit(e);
    return status == 0 ? 0 : kUserError;
  }

  engine::JobLoadOptions load;
  load.overrides = overrides;
  load.sweeps = sweeps;
  try {
    if (*run) {
      if (options.resume && options.overwrite) {
        throw engine::UsageError("--resume and --overwrite exclude each other");
      }
      require_own_output(overrides, sweeps, output);
      options.output = output;
      options.invocation = invocation;
      if (!runs_text.empty()) options.runs = parse_run_range(runs_text);
      if (!shard_text.empty()) {
        if (!runs_text.empty()) {
          throw engine::UsageError("--shard " + shard_text + " and --runs " + runs_text +
                                   " exclude each other: a shard is a range of runs");
        }
        engine::apply_shard_option(shard_text, job_path, load, options);
      }
      if (!quiet_rank) {  // a warning, printed under -q too
        const auto warning =
            engine::oversubscription_warning(options.threads, engine::affinity_cpus());
        if (warning) std::fprintf(stderr, "ggk: warning: %s\n", warning->c_str());
      }
#if GGK_WITH_MPI
      if (mpi && mpi->size() > 1) {
        engine::MpiRunOptions mpi_options;
        mpi_options.run = options;
        mpi_options.load = load;
        mpi_options.load.check_output = options.output.empty();
        mpi_options.rank_timeout_seconds = rank_timeout;
        return engine::run_job_over_mpi(*mpi, job_path, mpi_options);
      }
#endif
      load.check_output = options.output.empty();  // -o replaces the job's output
      return run_command(job_path, options, load);
    }
    if (quiet_rank) return 0;       // the other commands run on rank 0 alone
    std::ostream discard(nullptr);  // -q: what would be printed, dropped
    std::ostream& out = quiet ? discard : std::cout;
    if (*validate) {
      if (options.resume && options.overwrite) {
        throw engine::UsageError("--resume and --overwrite exclude each other");
      }
      return validate_command(job_path, output, load, options, quiet, print_job);
    }
    // The commands that read files ggk did not just write read them in a child
    // process: a file that crashes the HDF5 library is a damaged file
    // (run/isolated_reading.hpp).
    if (*info) {
      info_options.format = info_csv ? engine::InfoFormat::kCsv : engine::InfoFormat::kText;
      info_options.columns = engine::info_column_list(info_columns);
      if (!info_paired.empty()) info_options.paired = engine::parse_paired_option(info_paired);
      return engine::read_isolated({info_path}, [&] {
        engine::print_results_info(info_path, out, info_options, engine::metric_kind);
        return 0;
      });
    }
    if (*verify) {
      // A file that a live ggk writes now (its lock names a running process) may
      // be caught between its writes: it is verified into a scratch file, and what
      // looks damaged (or not yet a results file) is then said to be in writing,
      // exit 2 (verify it again later), not DAMAGED. The verifying child prints
      // directly otherwise.
      if (const auto writer = engine::OutputLock::writer_of(verify_path)) {
        return verify_while_written(verify_path, *writer, out);
      }
      try {
        return engine::read_isolated(
            {verify_path}, [&] { return engine::verify_results(verify_path, out) ? 0 : 1; });
      } catch (const engine::ReadingCrash& e) {
        out << verify_path << ": DAMAGED: reading it crashed the HDF5 library (" << e.how()
            << "): an object header is damaged where HDF5 does not check before it "
               "reads; ggk cannot read this file\n";
        return 1;
      }
    }
    if (*diff) {
      return engine::read_isolated({diff_files[0], diff_files[1]}, [&] {
        return engine::diff_results(diff_files[0], diff_files[1], out, diff_options) ? 0 : 1;
      });
    }
    if (*merge) {
      std::vector<std::filesystem::path> shards(merge_inputs.begin(), merge_inputs.end());
      if (!merge_output_option.empty()) {  // -o OUT: every positional is a shard
        if (!merge_output.empty()) shards.insert(shards.begin(), merge_output);
        merge_output = merge_output_option;
      }
      if (merge_job.empty() && (!merge_overrides.empty() || !merge_sweeps.empty())) {
        throw engine::UsageError(
            "merge: --set and --sweep say how the shards of --shards-of JOB were run (ggk merge "
            "--shards-of JOB --sweep ... -o OUT); shard files given by name need neither (ggk "
            "merge OUT a.h5 b.h5 ...)");
      }
      if (!merge_job.empty()) {
        if (!shards.empty()) {
          throw engine::UsageError("merge --shards-of " + merge_job +
                                   " finds the shards itself: give no shard files (or give "
                                   "them without --shards-of: ggk merge OUT a.h5 b.h5 ...)");
        }
        engine::JobLoadOptions shard_load;
        shard_load.overrides = merge_overrides;
        shard_load.sweeps = merge_sweeps;
        shards =
            engine::shards_of_job(merge_job, shard_load, merge_output, merge_options.allow_partial);
        merge_options.check_run_options = true;
        merge_options.expected_overrides = merge_overrides;
        merge_options.expected_sweeps = merge_sweeps;
      } else if (merge_output.empty() || shards.empty()) {
        throw engine::UsageError(
            "merge: give the output and its shards (ggk merge OUT a.h5 b.h5 ...), or the job "
            "whose shards to merge (ggk merge [OUT] --shards-of JOB)");
      }
      if (auto problem = engine::results_extension_problem(merge_output)) {
        throw engine::UsageError("merge output: " + *problem);
      }
      merge_options.program = invocation.front();
      return engine::merge_results_isolated(merge_output, shards, merge_options,
                                            quiet ? discard : std::cerr);
    }
  } catch (const engine::JobError& e) {
    if (!quiet_rank) std::fprintf(stderr, "ggk: error: %s\n", e.what());
    return kUserError;
  } catch (const engine::UsageError& e) {
    if (!quiet_rank) std::fprintf(stderr, "ggk: error: %s\n", e.what());
    return kUserError;
  } catch (const engine::RunFailure& e) {
    std::fprintf(stderr, "ggk: error: %s\n", e.what());
    return 1;
  } catch (const std::bad_alloc&) {  // the machine's memory or the user's limit, not a bug
    std::fprintf(stderr, "ggk: error: not enough memory: an allocation failed%s\n",
                 engine::address_space_limit_words().c_str());
    return kUserError;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ggk: internal error: %s\n", e.what());
    return 1;
  }
  return 0;
}
