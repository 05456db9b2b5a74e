#include "engine/store/dataset_schema.hpp"

#include <algorithm>
#include <array>
#include <cstddef>
#include <optional>
#include <stdexcept>
#include <vector>

namespace ggk::engine {

namespace {

// Fit datasets carry the prefix "fit:" (their path below the fit group).
constexpr std::string_view kFitPrefix = "fit:";

// What every run has, whatever its task: the samples, the graph, the fits'
// tables and the LSPI result of each fit. A task declares what it adds
// (TaskDefinition::datasets, engine/tasks/dataset_spec.hpp).
constexpr std::array kStoreDatasets = {
    DatasetSpec{"samples/observations", "sample,observation_dim", "task state units",
                "state vector of s (sims/<task>/README.md)"},
    DatasetSpec{"samples/actions", "sample", "action code", "action a (action_names)"},
    DatasetSpec{"samples/rewards", "sample", "reward", "reward r"},
    DatasetSpec{"samples/next_observations", "sample,observation_dim", "task state units",
                "state vector of s'"},
    DatasetSpec{"samples/terminals", "sample", "flag", "1 if s' ends the episode"},
    DatasetSpec{"action_names", "action", "", "the name of each action code"},
    DatasetSpec{"graph/indptr", "node_pointer", "index",
                "CSR row pointer of the sample graph (node + 1 entries)"},
    DatasetSpec{"graph/indices", "edge", "node id", "CSR column (neighbour) of each edge"},
    DatasetSpec{"graph/weights", "edge", "task state units",
                "Euclidean distance between the edge's state vectors"},
    DatasetSpec{"graph/nodes", "node,observation_dim", "task state units",
                "state vector of each graph node"},
    DatasetSpec{"fit_metrics", "row", "", "one row per fit of this run (the summary's columns)"},
    DatasetSpec{"metric_specs", "metric", "",
                "fit_metrics' metrics after status: name, kind, unit, meaning, low, high"},
    DatasetSpec{"fit:centers", "centre", "node id", "the graph node of each kernel centre"},
    DatasetSpec{"fit:weights", "coefficient", "",
                "w: coefficient a*p + j = action a, centre j (p = centres; pvf: eigenvector j)"},
    DatasetSpec{"fit:policy", "state", "action code", "greedy action per state"},
    DatasetSpec{"fit:history/policy_changes", "iteration", "states",
                "states whose greedy action changed"},
    DatasetSpec{"fit:history/weight_change", "iteration", "", "L2 norm of w_k - w_(k-1)"},
    DatasetSpec{"fit:history/relative_residual", "iteration", "",
                "norm(A w - b) / norm(b) of the iteration's solve"},
    DatasetSpec{"fit:history/rcond", "iteration", "",
                "LAPACK's reciprocal 1-norm condition estimate of A (with its ridge)"},
    DatasetSpec{"fit:history/dense_solve", "iteration", "flag",
                "1 if the system was factorised densely (LAPACK)"},
    DatasetSpec{"fit:A/indptr", "row_pointer", "index", "CSR row pointer of the last A"},
    DatasetSpec{"fit:A/indices", "nonzero", "coefficient", "CSR column of each entry of A"},
    DatasetSpec{"fit:A/data", "nonzero", "", "entries of A (BRM: its lower triangle)"},
    DatasetSpec{"fit:b", "coefficient", "", "b of the last evaluation system"},
};

// The store's declarations as one declarer's list.
constexpr std::string_view kStoreDeclarer = "every task (the store)";

bool matches(std::string_view pattern, std::string_view path) {
  if (!pattern.empty() && pattern.back() == '*') {
    return path.starts_with(pattern.substr(0, pattern.size() - 1));
  }
  return pattern == path;
}

// The task's lists in their order, then the store's; exact paths before patterns.
const DatasetSpec* find_spec(std::string_view key, std::span<const DatasetSpecs> task_specs) {
  for (const bool exact : {true, false}) {
    for (std::size_t list = 0; list <= task_specs.size(); ++list) {
      const std::span<const DatasetSpec> specs =
          list < task_specs.size() ? task_specs[list].specs : std::span(kStoreDatasets);
      for (const DatasetSpec& spec : specs) {
        if (exact ? spec.path == key : matches(spec.path, key)) return &spec;
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

constexpr std::string_view kWhereToDeclare =
    ": declare it beside the task that writes it (TaskDefinition::datasets, "
    "engine/tasks/dataset_spec.hpp) or, if every run has it, in "
    "engine/store/dataset_schema.cpp";

// Describes `object` (at `relative` below the run group) and every dataset below
// it, each object opened once through its open parent.
void describe_below(Hdf5File::Object& object, const std::string& relative,
                    std::span<const DatasetSpecs> task_specs) {
  if (object.kind() == Hdf5File::ObjectKind::kGroup) {
    for (const std::string& member : object.member_names()) {
      std::optional<Hdf5File::Object> child = object.hard_member(member);
      if (!child) {
        throw std::logic_error(object.path() + "/" + member + " is not a hard link");
      }
      describe_below(*child, relative.empty() ? member : relative + "/" + member, task_specs);
    }
    return;
  }
  const DatasetSpec* spec = dataset_spec_of(relative, task_specs);
  if (spec == nullptr) {
    throw std::logic_error("dataset '" + relative + "' has no declaration" +
                           std::string(kWhereToDeclare));
  }
  const std::size_t rank = object.dataset_shape().size();
  if (rank != dims_rank(spec->dims)) {
    throw std::logic_error("dataset '" + relative + "' has " + std::to_string(rank) +
                           " dimensions, its declaration names " + std::string(spec->dims) +
                           std::string(kWhereToDeclare));
  }
  describe(object, spec->dims, spec->units, spec->description);
}

void append_markdown_rows(std::string& text, std::string_view declared_by,
                          std::span<const DatasetSpec> specs) {
  for (const DatasetSpec& spec : specs) {
    std::string path(spec.path);
    if (path.starts_with(kFitPrefix)) {
      path = "fits/<basis>/<point>/" + path.substr(kFitPrefix.size());
    }
    text += "| `" + path + "` | " + std::string(declared_by) + " | " + std::string(spec.dims) +
            " | " + std::string(spec.units) + " | " + std::string(spec.description) + " |\n";
  }
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
      throw std::logic_error("dims '" + std::string(dims) + "': an axis name is " +
                             (axis.empty() ? "empty" : "'scalar' (a dataset of no dimension)"));
    }
    if (i < dims.size()) ++rank;
    start = i + 1;
  }
  return rank;
}

std::span<const DatasetSpec> store_dataset_specs() {
  return kStoreDatasets;
}

const DatasetSpec* dataset_spec_of(std::string_view relative,
                                   std::span<const DatasetSpecs> task_specs) {
  // fits/<basis>/<point>/rest -> "fit:rest"
  if (relative.starts_with("fits/")) {
    const std::size_t basis_end = relative.find('/', 5);
    const std::size_t point_end =
        basis_end == std::string_view::npos ? basis_end : relative.find('/', basis_end + 1);
    if (point_end == std::string_view::npos) return nullptr;
    std::string key(kFitPrefix);
    key += relative.substr(point_end + 1);
    return find_spec(key, task_specs);
  }
  if (relative.starts_with(kFitPrefix)) return nullptr;
  return find_spec(relative, task_specs);
}

void describe_datasets(Hdf5File& file, const std::string& run_group,
                       std::span<const DatasetSpecs> task_specs) {
  std::optional<Hdf5File::Object> group = file.open_hard_link(run_group);
  if (!group) throw std::logic_error(run_group + " is not a hard link");
  describe_below(*group, "", task_specs);
}

void describe_table(Hdf5File& file, const std::string& path, std::string_view description) {
  std::optional<Hdf5File::Object> table = file.open_hard_link(path);
  if (!table) throw std::logic_error(path + " is not a hard link");
  describe(*table, "row", "", description);
}

std::string dataset_schema_markdown(std::span<const DatasetSpecs> declared) {
  std::string text =
      "| dataset | declared by | dims | units | description |\n"
      "|---|---|---|---|---|\n";
  append_markdown_rows(text, kStoreDeclarer, kStoreDatasets);
  std::vector<std::string_view> written;
  for (const DatasetSpecs& list : declared) {
    if (std::find(written.begin(), written.end(), list.declared_by) != written.end()) continue;
    written.push_back(list.declared_by);
    append_markdown_rows(text, list.declared_by, list.specs);
  }
  return text;
}

}  // namespace ggk::engine
