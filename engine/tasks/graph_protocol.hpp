#pragma once
// What every task that learns on a sample graph shares (the discrete protocol:
// maze, arm, chain; Khepera): the run's graph as its fits see it (the centre
// order, the geodesic distances from the centres any fit uses, the graph
// diagnostics), the fits' metrics by name, the iteration history of the tested
// metrics, and the record of a fit that cannot start.
//
// A task declares its metrics (metric_spec.hpp: name, kind, unit, meaning,
// range, tested or not) in summary-column order; a fit sets them by name (FitMetrics); what the fit
// does not set is NaN. The graph metrics (graph_metric_specs) follow the task's own.
//
// Thread-safety: RunGraph is read-only once built and shared by the fits of a
// run; FitMetrics belongs to one fit.

#include <cstdint>
#include <functional>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "engine/job/sweep.hpp"
#include "engine/tasks/dataset_spec.hpp"
#include "engine/tasks/metric_spec.hpp"
#include "engine/tasks/run_record.hpp"
#include "kernels/csr_graph.hpp"
#include "kernels/eigen_types.hpp"

namespace ggk::engine {

// The metrics every graph task's fits carry after its own, in this order:
// lspi_iterations, graph_nodes and the diagnostics of kernels/graph_diagnostics.hpp
// (edges, median_degree, geodesic_stretch per run, kernel_gap per fit;
// engine/tasks/README.md). All means; lspi_iterations, graph_nodes and edges integers.
const std::vector<MetricSpec>& graph_metric_specs();

// The datasets every graph task's fits add (dataset_spec.hpp): a PVF basis's
// eigenvalues and the iteration history (weights, the tested metrics).
DatasetSpecs graph_dataset_specs();

// A fit's metrics by name, in the order of `specs` (which must outlive it).
class FitMetrics {
 public:
  explicit FitMetrics(std::span<const MetricSpec> specs);

  // Throws std::logic_error for a name `specs` does not declare.
  void set(std::string_view name, double value);
  double get(std::string_view name) const;

  std::span<const MetricSpec> specs() const { return specs_; }
  // (name, value) in declared order: FitRecord::metrics.
  std::vector<std::pair<std::string, double>> named_values() const;

 private:
  std::size_t index_of(std::string_view name) const;

  std::span<const MetricSpec> specs_;
  std::vector<double> values_;  // NaN until set
};

// The geodesic stretch of a run's graph is measured between its first 100
// centres (all nodes when fewer): a property of the run's graph, the same
// whatever kernel counts the job sweeps, so a fit's metrics never depend on the
// other fits of its job (a study grown by a kernel count equals the larger study
// from scratch). 100: the paper's largest Khepera kernel count; its pairs
// (4,950) give the median to well under 1 %.
inline constexpr std::int32_t kStretchCenters = 100;

// The run's sample graph as every fit of the run sees it.
struct RunGraph {
  std::int32_t nodes = 0;             // graph nodes: visited states, occupied SOM units
  std::vector<std::int32_t> centers;  // the centre order: a fit with p kernels uses the first p
  // Shortest paths from the first min(P, nodes) centres (P the largest kernel
  // count of the points: every centre any of the fits uses) to every node.
  kernels::RowMatrixXd center_distances;
  // The run's graph diagnostics (kernels/graph_diagnostics.hpp); the geodesic
  // stretch over the first min(kStretchCenters, nodes) centres.
  double edges = 0.0;
  double median_degree = 0.0;
  double geodesic_stretch = 0.0;
};

// Builds the RunGraph of `graph` (node_vectors: a row per node, for ED) with the
// given centre order over its nodes (is_node[u] != 0); the Dijkstra sources run
// in parallel (oneTBB).
RunGraph run_graph(const kernels::CsrGraph& graph, std::span<const std::uint8_t> is_node,
                   std::vector<std::int32_t> center_order, const kernels::RowMatrixXd& node_vectors,
                   std::span<const SweepPoint> points);

// Sets graph_nodes, edges, median_degree, geodesic_stretch and kernel_gap
// (lspi_iterations is the task's to set).
void set_graph_metrics(FitMetrics& metrics, const RunGraph& graph, double kernel_gap);

// The error that stops a run whose fit meets a kernel value that is not finite
// (kernels::NonFiniteKernelValue: a NaN or infinite observation, centre or
// distance): "run R, fit <basis> with P kernels, sigma S: <what>", naming the
// state and centre. Never a zero feature, never a fit recorded as if it were
// sound: the run fails (the CLI: exit status 1, what the file holds).
std::runtime_error non_finite_kernel_error(std::int32_t run, const SweepPoint& point,
                                           const std::exception& cause);

// The record of a fit that cannot start because it asks for more kernels than
// the graph has nodes: status "invalid", the message "run R: P kernels requested
// but <shortage>", the metrics of `specs` NaN but lspi_iterations (0) and the
// graph's (kernel_gap NaN).
FitRecord invalid_fit(const SweepPoint& point, std::int32_t run, const RunGraph& graph,
                      std::span<const MetricSpec> specs, std::string_view shortage);

// [lspi] evaluate_iterations: for every iterate of fit.lspi, its weights
// (history/weights, iterations x k) and the tested metrics of its greedy
// policy's test (history/<name>, one value per iterate, in declared order).
// test(w, metrics) sets the tested metrics of weights w. The last entries equal
// the fit's own metrics when the test is the fit's.
void add_iteration_history(
    FitRecord& fit, std::span<const MetricSpec> specs,
    const std::function<void(const Eigen::VectorXd& weights, FitMetrics& metrics)>& test);

}  // namespace ggk::engine
