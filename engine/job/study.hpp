#pragma once
// Studies: any scalar key of a job as a sweep axis, beside the five built-in
// axes (basis, kernels, sigma, solver, lambda; sweep.hpp).
//
//   [sweep]
//   kernels = [10, 20]
//   sigma = [1000.0]
//   "khepera.motion.turn_deg" = [15, 30, 45]        # an axis over any scalar key
//   [[sweep.zip]]                                    # keys that vary together
//   "khepera.sensors.noise_model" = ["additive", "multiplicative"]
//   "khepera.sensors.noise_fraction" = [0.0, 0.05]
//
// On the command line, `--sweep KEY=V1,V2,...` adds (or replaces) the axis
// `"KEY" = [V1, V2, ...]`; KEY may be a built-in axis (`--sweep kernels=10,20`).
//
// Axes combine as a Cartesian product, in file order, the last varying fastest;
// a [[sweep.zip]] block is one axis whose keys take their i-th values together.
//
// Stages. An axis changes the runs or only the fits:
// - fit-level: the built-in axes and the LSPI keys (`lspi.*` but
//   `lspi.fold_duplicates`, which changes the samples LSPI sees): more fits of
//   the same run, sharing its samples, graph and distances;
// - run-level: every other key (the task's table, `basis.*`,
//   `lspi.fold_duplicates`): a distinct *run configuration*, whose runs compute
//   their own samples and graph. A zip block with a run-level key is run-level.
// The unit of work is (run configuration, run number). Run r of every
// configuration draws from the same random streams (seeds.hpp keys them by
// (seed, run, purpose) alone): configurations compare paired by run (common
// random numbers).
//
// Every point's effective job is parsed and validated by the job reader before
// anything runs; an error names the axis and the value.
//
// Thread-safety: plain data.

#include <cstdint>
#include <string>
#include <vector>

#include <filesystem>
#include <span>

#include <toml++/toml.h>

#include "engine/job/job_file.hpp"
#include "engine/job/job_spec.hpp"
#include "engine/job/sweep.hpp"
#include "engine/job/task_table.hpp"

namespace ggk::engine {

enum class StageLevel { kRun, kFit };

// A study axis: one key, or the keys of a [[sweep.zip]] block.
struct StudyAxis {
  std::vector<std::string> keys;
  // values[i][k]: the i-th value of keys[k], canonical text.
  std::vector<std::vector<std::string>> values;
  StageLevel level = StageLevel::kRun;
};

// The fit-level study keys of one fit (`lspi.max_iterations = 50`), and the LSPI
// settings they make. Empty assignments: the configuration's own settings.
struct FitVariant {
  std::vector<AxisAssignment> assignments;
  LspiSettings lspi;
};

// The runs of one combination of run-level values.
struct RunConfiguration {
  std::int32_t index = 0;
  std::vector<AxisAssignment> assignments;  // run-level values, in axis order
  JobSpec job;                              // the effective job (its fits: expand_sweep)
  std::vector<FitVariant> variants;         // at least one
  // Where its runs live in a results file: job.configuration_group, empty for a
  // job without run-level axes (runs at /<task>/run_NNN, as always), else
  // "config_NNN" (the configuration's index): /<task>/config_NNN/run_NNN.
};

// One unit of work: a run of one run configuration; a plain job's units are its
// runs, configuration 0.
struct WorkUnit {
  std::int32_t configuration = 0;
  std::int32_t run = 0;
  // The indices (expand_points) of the sweep points to fit, ascending; empty:
  // every point.
  std::vector<std::int32_t> points = {};
  // Whether `points` extend a stored run: a complete run of a study grown by
  // fit-level values lacks their fits, only they are fitted and the run is
  // extended (store/run_extension.hpp); none: the run's fits are only
  // renumbered to the grown study's points. Else a new run of those points
  // only (an adaptive study's run that its decided cells no longer need all
  // of: store/adaptive_state.hpp).
  bool extends = false;
  bool operator==(const WorkUnit&) const = default;
};

struct Study {
  std::vector<StudyAxis> axes;                   // study axes, in file order
  std::vector<RunConfiguration> configurations;  // at least one
  bool has_axes() const { return !axes.empty(); }
  // The job every configuration shares name, runs, seed, task and output with.
  const JobSpec& job() const { return configurations.front().job; }
};

// The keys that may not be axes, and why (name, task, runs, seed, output.*).
// Empty when `key` may be one.
std::string forbidden_axis_reason(const std::string& key);

// Which stage a key changes.
StageLevel stage_of(const std::string& key);

// Reads a job file as a study (a plain job is a study of one configuration):
// every point parsed and validated. Throws JobError; an error at a point names
// the point ("... (at the study point khepera.motion.turn_deg = 400)").
Study parse_study(std::string toml_text, const std::filesystem::path& source_file,
                  std::span<const TaskTable> tasks, const JobLoadOptions& options = {});
Study load_study(const std::filesystem::path& path, std::span<const TaskTable> tasks,
                 const JobLoadOptions& options = {});

// The fits of one run of a configuration: expand_sweep(configuration.job), each
// point once per fit variant (the variant varying fastest), renumbered.
std::vector<SweepPoint> expand_points(const RunConfiguration& configuration);

// SweepPoint::variant_label of a variant's points.
std::string variant_label(const FitVariant& variant);
// A canonical value's text without its string quotes ("\"additive\"" -> "additive").
std::string unquoted(const std::string& value);

// A unit in words, for messages: "run 3", or in a study with run-level axes
// "run 3 of config_002".
std::string unit_words(const Study& study, WorkUnit unit);

// A study of one configuration: the plain job, its own LSPI settings.
Study study_of(JobSpec job);

// What the study computes, as one resolved configuration (what --resume
// compares): a plain job's own; a study's, its first configuration's with every
// axis key holding its array of values ("[15.0, 30.0]") and `study.axes` the
// axes' keys in order, zipped keys joined by '+'.
ResolvedConfig resolved_of(const Study& study);

// The study as a job file (`ggk validate --print`): every key the job reader
// read, with the value it used (defaults filled in), grouped into TOML tables;
// the study axes in [sweep] as quoted dotted keys, zipped ones as [[sweep.zip]]
// blocks. Read back, it is the same study (its resolved_of is equal).
std::string resolved_job_toml(const Study& study);

// A configuration's study values as stored with its group: `key = value`
// lines, in axis order.
std::string study_values_text(const std::vector<AxisAssignment>& assignments);

}  // namespace ggk::engine
