#include "engine/store/dataset_schema.hpp"

#include <array>
#include <cstddef>
#include <optional>
#include <stdexcept>
#include <vector>

namespace ggk::engine {

namespace {

// Fit datasets carry the prefix "fit:" (their path below the fit group).
constexpr std::string_view kFitPrefix = "fit:";

constexpr std::array kSchemas = {
    // samples/ (every task)
    DatasetSchema{"samples/observations", "sample,observation_dim", "task state units",
                  "state vector of s (sims/<task>/README.md)"},
    DatasetSchema{"samples/actions", "sample", "action code", "action a (action_names)"},
    DatasetSchema{"samples/rewards", "sample", "reward", "reward r"},
    DatasetSchema{"samples/next_observations", "sample,observation_dim", "task state units",
                  "state vector of s'"},
    DatasetSchema{"samples/terminals", "sample", "flag", "1 if s' ends the episode"},
    DatasetSchema{"samples/collisions", "sample", "flag",
                  "1 if the random step was undone (khepera)"},
    // the run
    DatasetSchema{"action_names", "action", "", "the name of each action code"},
    DatasetSchema{"start_states", "start", "node id",
                  "the states the goal test starts from, the index of steps_to_goal (maze, arm)"},
    DatasetSchema{"graph/indptr", "node_pointer", "index",
                  "CSR row pointer of the sample graph (node + 1 entries)"},
    DatasetSchema{"graph/indices", "edge", "node id", "CSR column (neighbour) of each edge"},
    DatasetSchema{"graph/weights", "edge", "task state units",
                  "Euclidean distance between the edge's state vectors"},
    DatasetSchema{"graph/nodes", "node,observation_dim", "task state units",
                  "state vector of each graph node"},
    DatasetSchema{"graph/visited", "node", "flag",
                  "1 if a sample starts or ends there (maze, arm)"},
    DatasetSchema{"graph/occupied", "node", "flag",
                  "1 if a reading has the SOM unit as its BMU (khepera)", "khepera"},
    DatasetSchema{"grid/state_of", "shoulder,elbow", "node id",
                  "arm: the state of each joint-grid cell, -1 = collision"},
    DatasetSchema{"grid/goal", "shoulder,elbow", "flag", "arm: 1 where the cell is a goal state"},
    DatasetSchema{"workspace/rectangles", "rectangle,corner_xy", "workspace units",
                  "arm obstacles: min x, min y, max x, max y"},
    DatasetSchema{"workspace/discs", "disc,disc_field", "workspace units",
                  "arm obstacles: centre x, y, radius"},
    DatasetSchema{"workspace/object", "disc_field", "workspace units",
                  "arm: the object, centre x, y, radius"},
    DatasetSchema{"workspace/pose_A", "joint_point,xy", "workspace units",
                  "arm: base, elbow and hand of pose A"},
    DatasetSchema{"workspace/pose_A_deg", "joint", "degrees", "arm: shoulder and elbow angle of A"},
    DatasetSchema{"workspace/goal_poses", "goal,pose_xy", "workspace units",
                  "arm: base, elbow and hand (x, y each) of each goal pose"},
    DatasetSchema{"workspace/goal_poses_deg", "goal,joint", "degrees",
                  "arm: shoulder and elbow angle of each goal pose"},
    DatasetSchema{"som/prototypes", "node,sensor", "IR reading",
                  "khepera: the prototype of each SOM unit", "khepera"},
    DatasetSchema{"som/grid", "node,grid_axis", "index",
                  "khepera: (row, column) of each unit on the SOM grid", "khepera"},
    DatasetSchema{"som/quantization_error", "epoch", "IR reading",
                  "khepera: mean distance to the BMU after each epoch", "khepera"},
    DatasetSchema{"state_units", "state", "node id",
                  "khepera: the BMU of every reading of the walks (series k, reading t: row "
                  "k (steps + 1) + t)",
                  "khepera"},
    DatasetSchema{"arena/box", "box_field", "cm", "khepera: min x, min y, max x, max y, walled"},
    DatasetSchema{"arena/segments", "segment,segment_field", "cm", "khepera: a x, a y, b x, b y"},
    DatasetSchema{"arena/rectangles", "rectangle,corner_xy", "cm",
                  "khepera: min x, min y, max x, max y"},
    DatasetSchema{"arena/rotated_rectangles", "rectangle,rotated_field", "cm, degrees",
                  "khepera: centre x, y, width, height, angle (degrees)"},
    DatasetSchema{"arena/discs", "disc,disc_field", "cm", "khepera: centre x, y, radius"},
    DatasetSchema{"arena/start", "pose", "cm, rad", "khepera: start x, y, heading"},
    DatasetSchema{"robot/radius", "value", "cm", "khepera: the body's radius"},
    DatasetSchema{"robot/sensors", "sensor,mount_field", "cm, degrees",
                  "khepera: each IR sensor's mount x, y, heading"},
    DatasetSchema{"robot/start_rays", "ray,ray_field", "cm, flag",
                  "khepera: three rays per sensor at the start pose: from x, y, to x, y, seen"},
    DatasetSchema{"robot/start_readings", "sensor", "IR reading",
                  "khepera: the noiseless readings at the start pose"},
    // continuous tasks (engine/tasks/continuous_protocol.hpp) other than the Khepera
    DatasetSchema{"observation_scale", "observation_dim", "task state units",
                  "the divisor of each observation dimension before the SOM and the kernels "
                  "([<task>.scale])"},
    DatasetSchema{"som/prototypes", "node,observation_dim", "scaled state units",
                  "the prototype of each SOM unit (observation / observation_scale)"},
    DatasetSchema{"som/grid", "node,grid_axis", "index",
                  "(row, column) of each unit on the SOM grid"},
    DatasetSchema{"som/quantization_error", "epoch", "scaled state units",
                  "mean distance to the BMU after each epoch"},
    DatasetSchema{"state_units", "state", "node id",
                  "the BMU of every observation of the walks, in series order"},
    DatasetSchema{"graph/occupied", "node", "flag",
                  "1 if an observation has the SOM unit as its BMU"},
    DatasetSchema{"fit:unit_policy", "node", "action code",
                  "greedy action at each SOM unit's prototype"},
    DatasetSchema{"fit:evaluation/returns", "episode", "reward", "the return of each test episode"},
    DatasetSchema{
        "fit:evaluation/trajectory_*", "step,state_field", "task state units",
        "the simulator's state along the test episode, the start first (sims/<task>/README.md)"},
    DatasetSchema{"optimal_actions", "state,action", "flag",
                  "chain: 1 where the action is optimal by value iteration"},
    DatasetSchema{"fit_metrics", "row", "", "one row per fit of this run (the summary's columns)"},
    DatasetSchema{"metric_specs", "metric", "",
                  "fit_metrics' metrics after status: name, kind, unit, meaning, low, high"},
    // a fit (fits/<basis>/<point>/)
    DatasetSchema{"fit:centers", "centre", "node id", "the graph node of each kernel centre"},
    DatasetSchema{"fit:weights", "coefficient", "",
                  "w: coefficient a*p + j = action a, centre j (p = centres; pvf: eigenvector j)"},
    DatasetSchema{"fit:laplacian_eigenvalues", "eigenvector", "1 (Laplacian eigenvalue)",
                  "basis pvf: the p smallest eigenvalues of the graph's Laplacian, ascending"},
    DatasetSchema{"fit:policy", "state", "action code", "greedy action per state"},
    DatasetSchema{"fit:state_values", "state", "return", "V(s) = max_a Q(s, a)"},
    DatasetSchema{"fit:steps_to_goal", "start", "steps",
                  "greedy steps from each of start_states to a goal, -1 = failed"},
    DatasetSchema{"fit:trajectory_*", "step", "node id",
                  "the states of the greedy walk from the named start, the start first"},
    DatasetSchema{"fit:unit_policy", "node", "action code",
                  "khepera: greedy action at each SOM unit's prototype", "khepera"},
    DatasetSchema{"fit:evaluation/returns", "episode", "reward",
                  "khepera: the return of each evaluation episode", "khepera"},
    DatasetSchema{"fit:evaluation/trajectory_*", "step,pose", "cm, rad",
                  "khepera: x, y, heading of the episode's poses from the start", "khepera"},
    DatasetSchema{"fit:history/policy_changes", "iteration", "states",
                  "states whose greedy action changed"},
    DatasetSchema{"fit:history/weight_change", "iteration", "", "L2 norm of w_k - w_(k-1)"},
    DatasetSchema{"fit:history/relative_residual", "iteration", "",
                  "norm(A w - b) / norm(b) of the iteration's solve"},
    DatasetSchema{"fit:history/rcond", "iteration", "",
                  "LAPACK's reciprocal 1-norm condition estimate of A (with its ridge)"},
    DatasetSchema{"fit:history/dense_solve", "iteration", "flag",
                  "1 if the system was factorised densely (LAPACK)"},
    DatasetSchema{"fit:history/weights", "iteration,coefficient", "", "w of every iteration"},
    DatasetSchema{"fit:history/*", "iteration", "as the metric",
                  "the task's test of every iteration's greedy policy (a metric)"},
    DatasetSchema{"fit:A/indptr", "row_pointer", "index", "CSR row pointer of the last A"},
    DatasetSchema{"fit:A/indices", "nonzero", "coefficient", "CSR column of each entry of A"},
    DatasetSchema{"fit:A/data", "nonzero", "", "entries of A (BRM: its lower triangle)"},
    DatasetSchema{"fit:b", "coefficient", "", "b of the last evaluation system"},
};

bool matches(std::string_view pattern, std::string_view path) {
  if (!pattern.empty() && pattern.back() == '*') {
    return path.starts_with(pattern.substr(0, pattern.size() - 1));
  }
  return pattern == path;
}

// The task's own entry first, then the entry for every task; exact paths before patterns.
const DatasetSchema* find_schema(std::string_view key, std::string_view task) {
  for (const bool exact : {true, false}) {
    for (const std::string_view owner : {task, std::string_view()}) {
      for (const DatasetSchema& schema : kSchemas) {
        if (schema.task != owner) continue;
        if (exact ? schema.path == key : matches(schema.path, key)) return &schema;
      }
    }
  }
  return nullptr;
}

void describe(Hdf5File::Object& object, std::string_view dims, std::string_view units,
              std::string_view description) {
  object.write_string_attribute("dims", dims);
  object.write_string_attribute("units", units);
  object.write_string_attribute("description", description);
}

// Describes `object` (at `relative` below the run group) and every dataset below
// it, each object opened once through its open parent.
void describe_below(Hdf5File::Object& object, const std::string& relative, std::string_view task) {
  if (object.kind() == Hdf5File::ObjectKind::kGroup) {
    for (const std::string& member : object.member_names()) {
      std::optional<Hdf5File::Object> child = object.hard_member(member);
      if (!child) {
        throw std::logic_error(object.path() + "/" + member + " is not a hard link");
      }
      describe_below(*child, relative.empty() ? member : relative + "/" + member, task);
    }
    return;
  }
  const DatasetSchema* schema = dataset_schema(relative, task);
  if (schema == nullptr) {
    throw std::logic_error("dataset '" + relative +
                           "' has no entry in engine/store/dataset_schema.cpp");
  }
  const std::size_t rank = object.dataset_shape().size();
  if (rank != dims_rank(schema->dims)) {
    throw std::logic_error("dataset '" + relative + "' has " + std::to_string(rank) +
                           " dimensions, engine/store/dataset_schema.cpp names " +
                           std::string(schema->dims));
  }
  describe(object, schema->dims, schema->units, schema->description);
}

}  // namespace

std::size_t dims_rank(std::string_view dims) {
  if (dims == kScalarDims) return 0;
  std::size_t rank = 1;
  std::size_t start = 0;
  for (std::size_t i = 0; i <= dims.size(); ++i) {
    if (i < dims.size() && dims[i] != ',') continue;
    const std::string_view axis = dims.substr(start, i - start);
    if (axis.empty() || axis == kScalarDims) {
      throw std::logic_error("dims '" + std::string(dims) +
                             "' in engine/store/dataset_schema.cpp: an axis name is " +
                             (axis.empty() ? "empty" : "'scalar' (a dataset of no dimension)"));
    }
    if (i < dims.size()) ++rank;
    start = i + 1;
  }
  return rank;
}

std::span<const DatasetSchema> dataset_schemas() {
  return kSchemas;
}

const DatasetSchema* dataset_schema(std::string_view relative, std::string_view task) {
  // fits/<basis>/<point>/rest -> "fit:rest"
  if (relative.starts_with("fits/")) {
    const std::size_t basis_end = relative.find('/', 5);
    const std::size_t point_end =
        basis_end == std::string_view::npos ? basis_end : relative.find('/', basis_end + 1);
    if (point_end == std::string_view::npos) return nullptr;
    std::string key(kFitPrefix);
    key += relative.substr(point_end + 1);
    return find_schema(key, task);
  }
  if (relative.starts_with(kFitPrefix)) return nullptr;
  return find_schema(relative, task);
}

void describe_datasets(Hdf5File& file, const std::string& run_group, std::string_view task) {
  std::optional<Hdf5File::Object> group = file.open_hard_link(run_group);
  if (!group) throw std::logic_error(run_group + " is not a hard link");
  describe_below(*group, "", task);
}

void describe_table(Hdf5File& file, const std::string& path, std::string_view description) {
  std::optional<Hdf5File::Object> table = file.open_hard_link(path);
  if (!table) throw std::logic_error(path + " is not a hard link");
  describe(*table, "row", "", description);
}

std::string dataset_schema_markdown() {
  std::string text =
      "| dataset (task: that task's entry; else every task's) | dims | units | description |\n"
      "|---|---|---|---|\n";
  for (const DatasetSchema& schema : kSchemas) {
    std::string path(schema.path);
    if (path.starts_with(kFitPrefix)) {
      path = "fits/<basis>/<point>/" + path.substr(kFitPrefix.size());
    }
    if (!schema.task.empty())
      path += "` (" + std::string(schema.task) + ")";
    else
      path += "`";
    text += "| `" + path + " | " + std::string(schema.dims) + " | " + std::string(schema.units) +
            " | " + std::string(schema.description) + " |\n";
  }
  return text;
}

}  // namespace ggk::engine
