#pragma once
// What a dataset of a run means, declared once beside whoever writes it: its path,
// the names of its axes, its units and a one-line description. A task (or the
// protocol it runs on) declares the arrays it adds (NamedArray, run_record.hpp);
// the store declares what every run has (samples/, graph/, a fit's weights and
// history: engine/store/dataset_schema.cpp). The store stamps the declaration on
// every dataset it writes (attributes `dims`, `units`, `description`) and refuses
// a dataset nobody declared; results/README.md's table of datasets is generated
// from the store's declarations and every registered task's.
// Plain data: no I/O, nothing of the store.
//
// Paths are relative to the run group, or to a fit group with the prefix "fit:"
// ("fit:steps_to_goal" is fits/<basis>/<point>/steps_to_goal); a trailing '*'
// matches any rest of the name ("fit:trajectory_*").
//
// Axes (`dims`, comma-separated, one name per dimension):
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
// and the small geometry axes named in each declaration (corner, pose_field, ...).
// `scalar` is not an axis: it is the whole `dims` of a dataset of no dimension
// (an HDF5 scalar dataspace, shape ()); a dataset of shape (1,) has one axis.

#include <span>
#include <string_view>

namespace ggk::engine {

struct DatasetSpec {
  std::string_view path;  // below the run group, or "fit:" + below a fit group
  std::string_view dims;  // comma-separated axis names, one per dimension
  std::string_view units;
  std::string_view description;
};

// One declarer's list: a protocol's (shared by the tasks that run on it) or one
// task's own. `declared_by` names it in results/README.md's table ("discrete
// tasks", "arm"); the lists of a task are searched in its order, so a task's own
// declaration of a path overrides its protocol's.
struct DatasetSpecs {
  std::string_view declared_by;
  std::span<const DatasetSpec> specs;
};

}  // namespace ggk::engine
