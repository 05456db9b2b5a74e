#pragma once
// The schema of a results file's root, in one place: the root attributes every
// ggk results file records (results/README.md lists them for readers), written
// and read only here; the layout version; which root attributes are provenance
// (noted by `ggk diff`, not compared); a fit's status. Where runs live under the
// root is run_store.hpp's.
//
// Root attributes (all scalars unless said):
//   job            string  the job's TOML text (with --set: the job they made)
//   job_file       string  the job file's path, as given
//   input:<key>    string  the text of each file the job names (key "maze.map_file")
//   ggk_version    string  "0.1.0"
//   git            string  `git describe` of the source ggk was built from
//   blas           string  the BLAS and LAPACK libraries (absent in older files)
//   created        string  UTC, "2024-06-01T12:00:00Z"
//   task           string  "maze", "arm", "khepera"
//   runs           int64   the job's run count
//   job_overrides  string  the --set arguments, one a line (only when given)
//   job_sweeps     string  the --sweep arguments, one a line (only when given)
//   job_resolved   string  every key with the value used, defaults filled in
//                          (job/resolved_config.hpp's text; absent in older files)
//   layout         int64   kLayoutVersion (absent in layout-1 files)
//   rules          int64   kResultsRules (results_rules.hpp; absent in older files)
//   runs_selected  int64[2] [A, B) of a shard written with --runs A:B (only then)
//   configurations_selected  int64[k]  the run configurations of an adaptive
//                  study's shard (--shard I/N: run/adaptive_shards.hpp; only then)
//   adaptive_cells int64   the whole study's cells, whose count sets each cell's
//                  level, on such a shard (only then)
//
// Call these on the thread that owns the file (StoreWriter's, in the engine).

#include <array>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "engine/hdf5/hdf5_file.hpp"
#include "engine/store/results_rules.hpp"

namespace ggk::engine {

// The layout of results files this ggk writes, recorded as the root attribute
// "layout": 2 = fit groups named by every axis value, variable-length UTF-8 strings
// in tables, integer arrays stored as integers. Files without it (layout 1, older
// ggk) are read by info, diff and verify, but runs are not added to them.
inline constexpr std::int64_t kLayoutVersion = 2;

// A file the job names, as the results record it: root attribute "input:<key>".
struct RecordedInput {
  std::string key;   // the job file's key, e.g. "maze.map_file"
  std::string text;  // the file's bytes
  bool operator==(const RecordedInput&) const = default;
};

// Runs [first, last) of a job: the selection a shard file was written for.
using RunsSelected = std::array<std::int64_t, 2>;

// The run configurations an adaptive study's shard was written for (their
// indices, ascending) and the cells of the whole study, which its shards judge
// at the whole study's level (store/adaptive_state.hpp).
struct ConfigurationsSelected {
  std::vector<std::int64_t> configurations;
  std::int64_t cells = 0;
  bool operator==(const ConfigurationsSelected&) const = default;
};

// The root attributes of a results file (the table above), as values.
struct ResultsHeader {
  std::string job;
  std::string job_file;
  std::vector<RecordedInput> inputs;  // ascending by key when read
  std::string ggk_version;
  std::string git;
  std::string blas;  // empty: no attribute (files of older ggk)
  std::string created;
  std::string task;
  std::int64_t runs = 0;
  std::string job_overrides;  // empty: no attribute (no --set)
  std::string job_sweeps;     // empty: no attribute (no --sweep)
  std::string job_resolved;   // empty: no attribute (files of older ggk)
  std::int64_t layout = kLayoutVersion;
  // The results rules (results_rules.hpp); of a file without the attribute, as
  // its `git` says (rules_of_unmarked_file).
  std::int64_t rules = kResultsRules;
  std::optional<RunsSelected> runs_selected;  // none: the whole job's file
  // none: not an adaptive study's shard
  std::optional<ConfigurationsSelected> configurations_selected;
  bool operator==(const ResultsHeader&) const = default;
};

// A file that is not a results file of ggk: a required root attribute is missing,
// or one has the wrong type. what() names the file and the attribute.
class ResultsHeaderError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Writes every attribute of `header` at the root of a file that has none of them
// yet (a new file, a merge's output).
void write_results_header(Hdf5File& file, const ResultsHeader& header);

// Replaces the attributes that say which job the file holds (job, job_file,
// runs, job_sweeps, job_overrides, job_resolved) by `header`'s: a grown study.
void rewrite_job_attributes(Hdf5File& file, const ResultsHeader& header);

// Reads the root attributes. job, job_file, ggk_version, git, created, task and runs
// are required; the others may be absent (layout then reads as 1). Throws
// ResultsHeaderError when a required one is missing, or when one does not read as
// its type (a string where an int64 belongs, damage): the message names the file
// and the attribute.
ResultsHeader read_results_header(const Hdf5File& file);

// Rewrites runs_selected alone (a resumed file is for the selection it was last
// run with); none removes it.
void write_runs_selected(Hdf5File& file, const std::optional<RunsSelected>& runs_selected);
// The same for an adaptive study's shard: configurations_selected and
// adaptive_cells, both or neither.
void write_configurations_selected(Hdf5File& file,
                                   const std::optional<ConfigurationsSelected>& selected);

// Why runs of this ggk cannot be added to a file of results layout `layout`
// ("it has results layout 1 (written by an older ggk ...)"), or an empty string
// when they can.
std::string layout_mismatch(std::int64_t layout);

// The name of the root attribute that holds an input file's text: "input:<key>".
std::string input_attribute_name(std::string_view key);

// What `ggk diff` does with a root attribute: compares it (the results), notes a
// difference (where and by what they were computed), or ignores it (wall-clock).
enum class RootAttributeRole { kResult, kProvenance, kWallClock };
RootAttributeRole root_attribute_role(std::string_view name);

// A fit's status: the fit group's attribute "status" and the summary's column.
// LSPI's outcome (kernels::to_string(LspiStatus)), or "invalid" for a fit that
// could not start (too few nodes, an unusable width).
// kEnvironmentFailed: the task's environment failed in the fit's test (a Python
// environment raised): the fit has weights but no test.
enum class FitStatus { kConverged, kMaxIterations, kSolverFailed, kInvalid, kEnvironmentFailed };
std::string_view to_string(FitStatus status);
// The status a text names, or none for a text of no status this ggk knows.
std::optional<FitStatus> fit_status_from_text(std::string_view text);
// A failed fit has no usable policy: it could not start, or its solver failed.
bool is_failed(FitStatus status);
// The same for a status as written ("solver_failed"); false for unknown texts.
bool is_failed_status(std::string_view text);

}  // namespace ggk::engine
