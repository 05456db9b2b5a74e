#pragma once
// Sweep job files (TOML): read, validate, and turn into a JobSpec before anything
// runs. Keys, types, defaults and ranges are documented in jobs/README.md.
// The reader knows the keys every job has; the task's own table is read by the
// parser among `tasks` whose name the job's `task` key gives (task_table.hpp;
// engine/tasks/task_list.hpp's task_tables() lists every registered task's).
//
// Every problem, from a TOML syntax error to an output directory that does not
// exist, is reported as one JobError naming the file, line, column and key
// (job_error.hpp). Nothing is created or written. Reentrant.

#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <toml++/toml.h>

#include "engine/job/job_error.hpp"
#include "engine/job/job_spec.hpp"
#include "engine/job/task_table.hpp"

namespace ggk::engine {

struct JobLoadOptions {
  // Replaces [output] file (the CLI's -o); the replacement's directory is checked
  // instead of the job file's.
  std::optional<std::filesystem::path> output_file;
  // Check that the output file's directory exists and is writable. Off for tools
  // that only read a job (e.g. re-reading the TOML stored in a results file).
  bool check_output = true;
  // "KEY=VALUE" (ggk run/validate --set): KEY a dotted key of the job
  // ("khepera.motion.turn_deg", "runs"), VALUE a TOML value (a bare word reads as
  // a string: --set sweep.solver=[\"brm\"] and --set name=x alike). Applied over the
  // file's table, in order, before validation; a bad value is reported naming
  // the option ("--set runs=0: runs: expected ...") instead of a line.
  std::vector<std::string> overrides;
  // "KEY=V1,V2,..." (ggk run/validate --sweep): the axis `"KEY" = [V1, V2, ...]` of
  // [sweep] (study.hpp), after the overrides; each value a TOML value or a bare
  // string, or KEY=[...] a TOML array.
  std::vector<std::string> sweeps;
};

// Why `file` cannot name a results file, or nothing: results are HDF5 files,
// named *.h5 or *.hdf5 (a results.csv would be an HDF5 file in disguise; CSV
// comes from `ggk info --csv`).
std::optional<std::string> results_extension_problem(const std::filesystem::path& file);

// The job file's TOML with the options' --set and --sweep applied. Throws JobError.
toml::table parse_job_toml(std::string_view toml_text, const std::string& file,
                           const JobLoadOptions& options);
// The job text recorded with the results: `toml_text` itself, or, with
// --set / --sweep, the job they make under a comment naming them.
std::string job_source_text(std::string toml_text, const toml::table& root, const std::string& file,
                            const JobLoadOptions& options);
// Validates one job's TOML (no study axes left in [sweep]). Throws JobError.
JobSpec parse_job_table(const toml::table& root, std::string source_text,
                        const std::filesystem::path& source_file, std::span<const TaskTable> tasks,
                        const JobLoadOptions& options);

// The text of the job file at `path` (a regular file of at most 16 MiB,
// job_input.hpp). Throws JobError naming the file.
std::string read_job_file(const std::filesystem::path& path);

// Reads and validates the job file at `path`. Throws JobError.
JobSpec load_job_file(const std::filesystem::path& path, std::span<const TaskTable> tasks,
                      const JobLoadOptions& options = {});

// Validates job TOML text. source_file names the text in messages, and its folder
// is where relative file names in the task's table are looked up. Throws JobError.
JobSpec parse_job(std::string toml_text, const std::filesystem::path& source_file,
                  std::span<const TaskTable> tasks, const JobLoadOptions& options = {});

}  // namespace ggk::engine
