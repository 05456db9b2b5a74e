#pragma once
// Where and how a run lives in the results file (schema: results/README.md).
//
//   /<task>/run_NNN/samples/{observations, actions, rewards, next_observations, terminals}
//   /<task>/run_NNN/graph/{indptr, indices, weights, nodes, ...}
//   /<task>/run_NNN/fits/<basis>/k_PPPP_sigmaS_<solver>_lambdaL/
//        {centers, weights, policy, history/..., A/, b, <task arrays>}  attrs: point values, status
//   /<task>/run_NNN/fit_metrics   one row per fit (the summary's columns)
//   /<task>/run_NNN               attr complete = 1, written last
//   /<task>/summary               rows of every complete run, in run order
//
// A study (engine/job/study.hpp) with run-level axes keeps each run
// configuration's runs in a group of its own, /<task>/config_NNN/run_NNN
// (attributes: configuration, study_values); every study's tables have one
// typed column per study key after `lambda` (attribute study_axes of
// fit_metrics and summary: their names, comma-separated). The summary lists
// configuration by configuration, with the column `configuration` after `run`
// (from the group's attribute: a run's own tables never hold its index).
//
// All functions make HDF5 calls: call them on the StoreWriter's thread only.

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "engine/hdf5/hdf5_file.hpp"
#include "engine/job/job_spec.hpp"
#include "engine/tasks/run_record.hpp"

namespace ggk::engine {

std::string run_group(const std::string& task, std::int32_t run);  // "/maze/run_007"
// Where a run is written before it is moved into place: "/.staging/maze/run_007".
inline const std::string kStagingRoot = "/.staging";
std::string staging_group(const std::string& task, std::int32_t run);
// True for the root members that are the writer's scratch (".staging" and the
// ".staging_discarded_N" of damaged leftovers): not results; readers skip them.
bool is_scratch(std::string_view root_member);
// "ggk/k_0016_sigma2.5_brm_lambda1e-06": every axis value, whatever the job sweeps
// (numbers in their shortest exact form, so distinct values get distinct names).
std::string fit_group_name(const SweepPoint& point);
std::string fit_group_name(const JobSpec& job, const SweepPoint& point);  // the same name

// The columns of fit_metrics and summary for a task whose fits report `metrics`
// (float64, those named in `integer_metrics` int64); of a study's: with the
// configuration column and the study keys' columns.
std::vector<TableColumn> summary_columns(const std::vector<std::string>& metric_names,
                                         const std::vector<std::string>& integer_metrics = {});
std::vector<TableColumn> summary_columns(const std::vector<std::string>& metric_names,
                                         bool configuration,
                                         const std::vector<AxisAssignment>& study_values,
                                         const std::vector<std::string>& integer_metrics = {});
inline constexpr const char* kStudyAxesAttribute = "study_axes";
// A fit's axis values as its fit_metrics row holds them (basis, kernels, sigma,
// solver, lambda, then the study values), and those columns' names.
TableRow point_axis_cells(const SweepPoint& point);
std::vector<std::string> point_axis_names(const SweepPoint& point);

// Where a job's runs live under the root, without the leading '/': its task
// ("khepera"), or a study configuration's group ("khepera/config_003"). Every
// function below that takes a `task` takes such a location.
std::string runs_location(const JobSpec& job);
// The run locations a file holds for `task`: its configuration groups, in
// index order, or the task itself when it has none.
std::vector<std::string> runs_locations(const Hdf5File& file, const std::string& task);
bool is_configuration_group_name(std::string_view name);
// A study configuration's group (/<task>/config_NNN) records its configuration
// in two attributes: `configuration` (int64, its index in the study's product
// order) and `study_values` (its "key = value" lines, canonical TOML values:
// what names the group's configuration whatever its name or index).
inline constexpr const char* kConfigurationAttribute = "configuration";
inline constexpr const char* kStudyValuesAttribute = "study_values";
// Creates the group at `location` (without the leading '/') when missing and
// (re)writes its two attributes.
void write_configuration_group(Hdf5File& file, const std::string& location, std::int64_t index,
                               const std::string& study_values);
// The index a configuration group records (attribute `configuration`); throws
// std::runtime_error when it has none.
std::int32_t configuration_of(const Hdf5File& file, const std::string& location);
// Whether the group at `location` records `index` as its configuration.
bool records_configuration(const Hdf5File& file, const std::string& location, std::int64_t index);
// The study_values the group at `location` records; nullopt when it has none.
std::optional<std::string> study_values_of(const Hdf5File& file, const std::string& location);

// Writes the run whole under its staging group, flushes, moves it into place,
// marks it complete and flushes again (an incomplete leftover of the same run is
// removed first). A kill at any moment leaves every complete run readable.
void write_run(Hdf5File& file, const JobSpec& job, const RunRecord& record);
// Its two steps: the run written whole under its staging group (a leftover there
// abandoned), its digest set, flushed; returns the staging group's path. Then
// the staged run moved into place (an earlier copy there abandoned), marked
// complete, flushed.
std::string stage_run(Hdf5File& file, const JobSpec& job, const RunRecord& record);
void commit_staged_run(Hdf5File& file, const std::string& location, std::int32_t run);

// The run as the bytes of an in-memory HDF5 file that holds its group, written
// by write_run (for a run computed on another MPI rank).
std::vector<unsigned char> run_image(const JobSpec& job, const RunRecord& record);

// Commits a run from run_image()'s bytes as write_run commits a record: the group
// is copied under its staging path, flushed, moved into place and flushed again,
// so the file ends up holding what write_run would have written. Throws
// std::runtime_error when the image does not hold that run complete.
void write_run_image(Hdf5File& file, const JobSpec& job, std::int32_t run,
                     std::span<const unsigned char> image);

bool run_is_complete(const Hdf5File& file, const std::string& task, std::int32_t run);

// The ids in [0, runs) of the run groups stored under /<task> (complete or not),
// ascending; and of the complete ones. They list the task group, so their cost
// follows what the file holds, not `runs` (a shard of a job of 2^31 runs).
std::vector<std::int32_t> stored_runs(const Hdf5File& file, const std::string& task,
                                      std::int32_t runs);
std::vector<std::int32_t> complete_runs(const Hdf5File& file, const std::string& task,
                                        std::int32_t runs);

// Abandons (detaches without reading or freeing) what a killed or failed writer
// left: the staging groups and runs not marked complete; returns the ids of the
// complete ones.
std::vector<std::int32_t> prepare_for_resume(Hdf5File& file, const JobSpec& job);

// Takes a (damaged) run out of the results without reading below it: detached,
// its space left unused (or, if its header does not read, its link moved aside).
void discard_run(Hdf5File& file, const std::string& task, std::int32_t run);

// Removes the whole staging group (this session's scratch of finished writes).
void drop_staging(Hdf5File& file);

// (Re)writes /<task>/summary from the fit_metrics of every complete run, staged
// (a column takes the first run's type: a whole-number metric of a run written
// as float64 by an older ggk and as int64 now is converted, never rounded)
// (written whole under /.staging, then moved into place), and removes the
// staging group: call it when no run is being written. Returns the number of rows.
std::int64_t write_summary(Hdf5File& file, const JobSpec& job);
// The same for a file whose job is known only by its task and run count.
std::int64_t write_summary(Hdf5File& file, const std::string& task, std::int32_t runs);

}  // namespace ggk::engine
