#pragma once
// What every dataset of a run means: the store declares what every run has
// (samples/, graph/, a fit's weights, policy and LSPI history) and reads what a
// task adds from the run's declarations (RunRecord::dataset_specs, declared beside
// the task: engine/tasks/dataset_spec.hpp). The writer stamps each dataset's
// declaration on it (attributes `dims`, `units`, `description`), and
// results/README.md's table of datasets is generated from the store's and every
// registered task's declarations (tests/engine/store/dataset_schema_test.cpp
// checks it). The axes are named in engine/tasks/dataset_spec.hpp.
//
// Dimension scales (H5DS) are not used: they store object references
// (file addresses) in DIMENSION_LIST / REFERENCE_LIST attributes, which HDF5's
// object copy leaves pointing into the source file when a run moves between
// files (ggk merge, a run computed on another MPI rank), and which would make
// the run digest and `ggk diff` depend on where HDF5 put each object.

#include <cstddef>
#include <span>
#include <string>
#include <string_view>

#include "engine/hdf5/hdf5_file.hpp"
#include "engine/tasks/dataset_spec.hpp"

namespace ggk::engine {

// The `dims` of a dataset of no dimension (rank 0).
inline constexpr std::string_view kScalarDims = "scalar";

// The rank that `dims` names: 0 for kScalarDims, else the number of
// comma-separated axis names. An empty axis name, or "scalar" among several, is a
// programmer error (std::logic_error).
std::size_t dims_rank(std::string_view dims);

// The store's own declarations: what every run has, in results/README.md's order.
std::span<const DatasetSpec> store_dataset_specs();

// The declaration of a dataset at `relative` below a run group ("samples/actions",
// "fits/ggk/k_0016_sigma5_brm_lambda1e-06/history/rcond"): the first of the
// task's lists (in order) that declares it, else the store's; exact paths before
// patterns. nullptr when none does.
const DatasetSpec* dataset_spec_of(std::string_view relative,
                                   std::span<const DatasetSpecs> task_specs = {});

// Writes `dims`, `units` and `description` on every dataset below `run_group`
// (call it before the run's digest is taken). A dataset without a declaration, or
// whose rank differs from its declaration's axes, is a programmer error
// (std::logic_error naming it and where to declare it).
void describe_datasets(Hdf5File& file, const std::string& run_group,
                       std::span<const DatasetSpecs> task_specs);

// Describes a table (fit_metrics, summary): axis `row`.
void describe_table(Hdf5File& file, const std::string& path, std::string_view description);

// The markdown table that results/README.md holds: the store's declarations,
// then each list of `declared` (every registered task's TaskDefinition::datasets,
// in task order; a list shared by several tasks, the same `declared_by`, once).
std::string dataset_schema_markdown(std::span<const DatasetSpecs> declared);

}  // namespace ggk::engine
