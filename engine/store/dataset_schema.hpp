#pragma once
// What every dataset of a run means: the names of its axes, its units and a
// description, in one table that the writer stamps on each dataset (attributes
// `dims`, `units`, `description`) and that results/README.md's table of axes is
// generated from (tests/engine/store/dataset_schema_test.cpp checks it).
//
// Axes (the `dims` attribute, comma-separated, one name per dimension):
//   sample     a transition of samples/           node    a node of the sample graph
//   state      a state of the LSPI fit (maze, arm, chain: a graph node, the
//              same id; Khepera: a reading of the walks, state_units its unit)
//   action     an action code (action_names names them)
//   centre     a kernel centre of the fit (centers: its node)
//   coefficient  a basis function: column a*p + j = action a, centre j
//              (weights, b; python/ggk_results reshapes w to (action, centre))
//   start      a start state of the goal test (start_states: its node)
//   iteration  an LSPI iteration          episode  an evaluation episode
//   step       a step of a walk           row      a table row
//   value      the one element of a single number kept as a 1-element array
//              (robot/radius)
// and the small geometry axes named in each entry (corner, pose_field, ...).
// `scalar` is not an axis: it is the whole `dims` of a dataset of no dimension
// (an HDF5 scalar dataspace, shape ()); a dataset of shape (1,) has one axis.
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

namespace ggk::engine {

struct DatasetSchema {
  std::string_view path;  // relative to the run group, or to a fit group ("fit:..."); a
                          // trailing '*' matches any rest of the name
  std::string_view dims;  // comma-separated axis names, one per dimension
  std::string_view units;
  std::string_view description;
  std::string_view task = {};  // empty: every task's; a task's name: that task's own, first
};

// The `dims` of a dataset of no dimension (rank 0).
inline constexpr std::string_view kScalarDims = "scalar";

// The rank that `dims` names: 0 for kScalarDims, else the number of
// comma-separated axis names. An empty axis name, or "scalar" among several, is a
// programmer error (std::logic_error).
std::size_t dims_rank(std::string_view dims);

// Every entry, run datasets first, in the order results/README.md lists them.
std::span<const DatasetSchema> dataset_schemas();

// The entry of a dataset at `relative` below a run group of `task`
// ("samples/actions", "fits/ggk/k_0016_sigma5_brm_lambda1e-06/history/rcond"):
// the task's own entry if it has one, else the entry for every task; nullptr
// when neither exists.
const DatasetSchema* dataset_schema(std::string_view relative, std::string_view task = {});

// Writes `dims`, `units` and `description` on every dataset below `run_group`
// (call it before the run's digest is taken). A dataset without an entry, or
// whose rank differs from its entry's axes, is a programmer error
// (std::logic_error naming it and this file).
void describe_datasets(Hdf5File& file, const std::string& run_group, std::string_view task);

// Describes a table (fit_metrics, summary): axis `row`.
void describe_table(Hdf5File& file, const std::string& path, std::string_view description);

// The markdown table of dataset_schemas() that results/README.md holds.
std::string dataset_schema_markdown();

}  // namespace ggk::engine
