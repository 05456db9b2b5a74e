#pragma once
// Everything one run produces, as plain data: what a task's compute_run returns
// (computed in parallel) and the store writes (on the one writer thread). Includes
// nothing else of tasks/ but the vocabulary of metrics and datasets
// (metric_spec.hpp, dataset_spec.hpp), so the store may read it without knowing
// any task.

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "engine/job/sweep.hpp"
#include "engine/tasks/dataset_spec.hpp"
#include "engine/tasks/metric_spec.hpp"
#include "kernels/csr_graph.hpp"
#include "kernels/eigen_types.hpp"
#include "kernels/lspi.hpp"

namespace ggk::engine {

// Transitions in D4RL's names; observations are state vectors, one row each.
struct SampleRecord {
  kernels::RowMatrixXd observations;
  std::vector<std::int32_t> actions;
  std::vector<double> rewards;
  kernels::RowMatrixXd next_observations;
  std::vector<std::uint8_t> terminals;
};

// How a NamedArray is stored: its values are held as doubles and written as
// this type (integers and flags as integers, so that h5py and pandas read them
// as such). Integer types need every value to be an integer in the type's range.
enum class ElementType { kFloat64, kInt32, kInt64, kUInt8 };

// A named array stored with a fit or a run (task-specific extras such as
// per-start-state step counts or value surfaces).
struct NamedArray {
  std::string name;
  std::vector<std::int64_t> shape;  // row-major; product = values.size()
  std::vector<double> values;
  ElementType element_type = ElementType::kFloat64;  // 2-D: kFloat64 or kInt32
};

struct FitRecord {
  SweepPoint point;
  std::string status;   // kernels::to_string(LspiStatus), or "invalid" when the fit could not start
  std::string message;  // why, when not converged
  // A caveat whatever the status (a PVF basis the graph does not determine,
  // pvf_basis.hpp); empty when none. Stored as the fit's attribute `warning`
  // only when not empty, and `ggk run` prints one line per fit kind.
  std::string warning;
  std::vector<std::int32_t> centers;  // graph node ids of the kernel centres
  kernels::LspiResult lspi;
  // Deterministic metrics, in a fixed order per task (the summary's columns).
  std::vector<std::pair<std::string, double>> metrics;
  std::vector<NamedArray> arrays;
  double fit_seconds = 0.0;  // wall time; the only non-deterministic number
};

struct RunRecord {
  std::int32_t run = 0;
  std::int32_t configuration = 0;  // its run configuration's index in a study (study.hpp)
  SampleRecord samples;
  kernels::CsrGraph graph;
  kernels::RowMatrixXd node_states;       // graph.num_nodes rows
  std::vector<NamedArray> arrays;         // task-specific run data
  std::vector<std::string> action_names;  // of action codes 0, 1, ... (dataset action_names)
  // The declarations of the fits' metrics (FitRecord::metrics), in their order:
  // written as the run's metric_specs; the integer ones (lspi_iterations, ...)
  // are int64 columns of fit_metrics and int64 attributes of the fit groups.
  std::vector<MetricSpec> metric_specs;
  // The task's declarations of the arrays it adds (TaskDefinition::datasets, set
  // by the runner): the store describes each dataset by them (dataset_spec.hpp).
  std::vector<DatasetSpecs> dataset_specs;
  std::vector<FitRecord> fits;  // one per sweep point, in sweep order
  // The fits are those a stored complete run lacks (WorkUnit::points): the
  // store extends that run with them (store/run_extension.hpp).
  bool extension = false;
  // Wall time the unit took to compute (job_runner's compute_units): the progress
  // display's cost of its configuration; never written to the file.
  double compute_seconds = 0.0;
};

}  // namespace ggk::engine
