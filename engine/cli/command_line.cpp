#include "engine/cli/command_line.hpp"

#include <optional>
#include <string_view>

#include "engine/job/spelling.hpp"
#include "engine/job/usage_error.hpp"
#include "engine/run/open_results.hpp"
#if GGK_WITH_PYTHON
#include "engine/tasks/python_env/python_runtime.hpp"
#endif

namespace ggk::engine {

namespace {

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

}  // namespace

CommandLine::CommandLine() {
  app.require_subcommand(1);
#if GGK_WITH_PYTHON
  const std::string embedded = "; python_env embeds " + python::embedded_version();
#else
  const std::string embedded = "; built without Python (no python_env task)";
#endif
  app.set_version_flag("--version", "ggk " + ggk_version_text() + embedded);

  run = app.add_subcommand("run", "Run a sweep job file, writing one HDF5 file");
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

  validate = app.add_subcommand("validate", "Check a job file and exit");
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
  validate->add_flag("--print", print_job,
                     "print the resolved job as TOML (every key, defaults filled in) and exit");
  // -q on every command: nothing on standard output, no progress or summary on
  // standard error; errors and warnings (a damaged run redone) still print.
  validate->add_flag("-q,--quiet", quiet, "print nothing but errors");
  info = app.add_subcommand("info", "Describe a results file");
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
  verify = app.add_subcommand(
      "verify", "Read every dataset of a results file back: exit 0 when whole, 1 when damaged");
  verify->add_option("file", verify_path, "results file (HDF5)")->required();
  verify->add_flag("-q,--quiet", quiet, "print nothing but errors: the exit status says it");
  diff = app.add_subcommand(
      "diff", "Exit 0 when two results files hold the same results, 1 (naming them) when not");
  diff->add_option("files", diff_files, "two results files")->required()->expected(2);
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
  merge = app.add_subcommand(
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
}

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
    const auto closest = closest_spelling(word, views);
    return closest ? " (did you mean '" + std::string(*closest) + "'?)" : std::string();
  };
  if (first.empty() || first[0] != '-') {
    if (command == nullptr) {
      std::string list;
      for (const std::string& name : names) list += (list.empty() ? "" : ", ") + name;
      throw UsageError("unknown command '" + first + "'" + suggestion(first, names) +
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
        throw UsageError("'" + arg + "': ggk takes no bare KEY=VALUE; write --set " + arg +
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
      throw UsageError("unknown option '" + name + "' for 'ggk " + first + "'" +
                       suggestion(name, options) + " (ggk " + first + " --help)");
    }
    // Skip the option's value, which may start with '-'.
    if (option->get_items_expected_min() > 0 && arg.find('=') == std::string::npos &&
        (is_long || arg.size() == 2)) {
      ++i;
    }
  }
}

}  // namespace ggk::engine
