#pragma once
// The metrics' declarations in a results file (tasks/metric_spec.hpp): the table
// metric_specs beside a run's fit_metrics, and beside the summary, one row per
// metric column in column order, fit_seconds last:
//
//   name   kind                            unit    meaning   low     high
//   str    "mean"|"indicator"|"fraction"   str     str       float64 float64
//
// (an unbounded side is -inf or inf). pandas.DataFrame(h5py.File(f)[path][:])
// reads it in one call; python/ggk_results reads kinds, units and ranges from it.
// Files written before it (ggk before 2026-11-29) have none: their readers take
// legacy_metric_spec(), the kinds those ggk versions gave by name.
//
// HDF5 calls: one thread at a time (the StoreWriter's while a job writes).

#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "engine/hdf5/hdf5_file.hpp"
#include "engine/tasks/metric_spec.hpp"

namespace ggk::engine {

inline constexpr const char* kMetricSpecsTable = "metric_specs";

// Writes `specs` as a new table at `path`.
void write_metric_specs(Hdf5File& file, const std::string& path, std::span<const MetricSpec> specs);

// The declarations of the table at `path`; nullopt when there is none. Throws
// std::runtime_error naming the path for a table that is not one (a missing
// column, an unknown kind, low > high).
std::optional<std::vector<MetricSpec>> read_metric_specs(const Hdf5File& file,
                                                         const std::string& path);

// Unites into `declared` the metric_specs of the run group at `run_group`
// (nothing for a run written before them): what the summary and `ggk info`
// hold for a file's runs.
void unite_run_metric_specs(const Hdf5File& file, const std::string& run_group,
                            std::optional<std::vector<MetricSpec>>& declared);

// What a file without metric_specs means by `metric`, as ggk read such files:
// success_from_<name> an indicator; success_rate, optimal_action_fraction and a
// name ending in _fraction a fraction in [0, 1]; anything else an unbounded mean.
// No unit, no meaning.
MetricSpec legacy_metric_spec(std::string_view metric);

}  // namespace ggk::engine
