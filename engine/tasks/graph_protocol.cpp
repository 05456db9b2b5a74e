#include "engine/tasks/graph_protocol.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <limits>
#include <stdexcept>

#include "kernels/graph_diagnostics.hpp"
#include "kernels/shortest_paths.hpp"

namespace ggk::engine {

const std::vector<MetricSpec>& graph_metric_specs() {
  static const std::vector<MetricSpec> specs = {
      integer(mean_metric("lspi_iterations", "iterations",
                          "LSPI iterations the fit took (up to lspi.max_iterations)", 0.0)),
      integer(mean_metric("graph_nodes", "nodes",
                          "nodes of the run's sample graph (visited states, occupied SOM units)",
                          0.0)),
      integer(mean_metric("edges", "edges", "undirected edges of the run's sample graph", 0.0)),
      mean_metric("median_degree", "edges", "median number of neighbours of the graph's nodes",
                  0.0),
      mean_metric("geodesic_stretch", "1",
                  "median over pairs of the first 100 centres of shortest-path over "
                  "straight-line distance",
                  0.0),
      mean_metric("kernel_gap", "1",
                  "mean over states and centres of |geodesic - ordinary Gaussian kernel value|",
                  0.0, 1.0)};
  return specs;
}

FitMetrics::FitMetrics(std::span<const MetricSpec> specs)
    : specs_(specs), values_(specs.size(), std::numeric_limits<double>::quiet_NaN()) {}

std::size_t FitMetrics::index_of(std::string_view name) const {
  for (std::size_t i = 0; i < specs_.size(); ++i) {
    if (specs_[i].name == name) return i;
  }
  throw std::logic_error("metric '" + std::string(name) + "' is not declared by the task");
}

void FitMetrics::set(std::string_view name, double value) {
  values_[index_of(name)] = value;
}

double FitMetrics::get(std::string_view name) const {
  return values_[index_of(name)];
}

std::vector<std::pair<std::string, double>> FitMetrics::named_values() const {
  std::vector<std::pair<std::string, double>> result;
  result.reserve(specs_.size());
  for (std::size_t i = 0; i < specs_.size(); ++i) result.emplace_back(specs_[i].name, values_[i]);
  return result;
}

namespace {

// The stretch between the first `count` centres. Their shortest paths are the
// first rows of center_distances when the fits need as many; the missing rows
// are computed in batches no larger than center_distances (at least one row),
// keeping only the centres' columns: no more memory than the fits' rows take.
double centre_stretch(const kernels::CsrGraph& graph, const RunGraph& result, std::int32_t count,
                      const kernels::RowMatrixXd& node_vectors) {
  const auto centers =
      std::span<const std::int32_t>(result.centers).first(static_cast<std::size_t>(count));
  if (result.center_distances.rows() >= count) {
    return kernels::geodesic_stretch(result.center_distances, centers, node_vectors);
  }
  // Between the centres only: row i, column j = SP(c_i, c_j), with the centres'
  // own vectors, indexed 0..count-1.
  kernels::RowMatrixXd between(count, count);
  kernels::RowMatrixXd vectors(count, node_vectors.cols());
  for (std::int32_t j = 0; j < count; ++j) vectors.row(j) = node_vectors.row(centers[j]);
  const auto known = static_cast<std::int32_t>(result.center_distances.rows());
  const std::int32_t batch = std::max<std::int32_t>(1, known);
  for (std::int32_t first = 0; first < count; first += batch) {
    const std::int32_t rows = std::min(batch, count - first);
    const bool stored = first + rows <= known;
    const kernels::RowMatrixXd computed =
        stored
            ? kernels::RowMatrixXd()
            : kernels::geodesic_distances(graph, centers.subspan(static_cast<std::size_t>(first),
                                                                 static_cast<std::size_t>(rows)));
    for (std::int32_t i = 0; i < rows; ++i) {
      for (std::int32_t j = 0; j < count; ++j) {
        between(first + i, j) =
            stored ? result.center_distances(first + i, centers[j]) : computed(i, centers[j]);
      }
    }
  }
  std::vector<std::int32_t> order(static_cast<std::size_t>(count));
  for (std::int32_t j = 0; j < count; ++j) order[static_cast<std::size_t>(j)] = j;
  return kernels::geodesic_stretch(between, order, vectors);
}

}  // namespace

RunGraph run_graph(const kernels::CsrGraph& graph, std::span<const std::uint8_t> is_node,
                   std::vector<std::int32_t> center_order, const kernels::RowMatrixXd& node_vectors,
                   std::span<const SweepPoint> points) {
  RunGraph result;
  result.nodes = static_cast<std::int32_t>(std::count(is_node.begin(), is_node.end(), 1));
  result.centers = std::move(center_order);
  std::int32_t max_kernels = 0;
  for (const SweepPoint& p : points) max_kernels = std::max(max_kernels, p.kernels);
  const auto sources = std::span<const std::int32_t>(result.centers)
                           .first(static_cast<std::size_t>(std::min(max_kernels, result.nodes)));
  result.center_distances = kernels::geodesic_distances(graph, sources);
  result.edges = static_cast<double>(kernels::undirected_edge_count(graph));
  result.median_degree = kernels::median_degree(graph, is_node);
  result.geodesic_stretch =
      centre_stretch(graph, result, std::min(kStretchCenters, result.nodes), node_vectors);
  return result;
}

void set_graph_metrics(FitMetrics& metrics, const RunGraph& graph, double kernel_gap) {
  metrics.set("graph_nodes", static_cast<double>(graph.nodes));
  metrics.set("edges", graph.edges);
  metrics.set("median_degree", graph.median_degree);
  metrics.set("geodesic_stretch", graph.geodesic_stretch);
  metrics.set("kernel_gap", kernel_gap);
}

std::runtime_error non_finite_kernel_error(std::int32_t run, const SweepPoint& point,
                                           const std::exception& cause) {
  char sigma[32];  // the shortest text that reads back as the width
  const auto end = std::to_chars(sigma, sigma + sizeof sigma - 1, point.sigma).ptr;
  *end = '\0';
  return std::runtime_error(
      "run " + std::to_string(run) + ", fit " + std::string(kernel_type_name(point.basis)) +
      " with " + std::to_string(point.kernels) + " kernels, sigma " + sigma + ": " + cause.what());
}

FitRecord invalid_fit(const SweepPoint& point, std::int32_t run, const RunGraph& graph,
                      std::span<const MetricSpec> specs, std::string_view shortage) {
  FitMetrics metrics(specs);
  metrics.set("lspi_iterations", 0.0);
  set_graph_metrics(metrics, graph, std::numeric_limits<double>::quiet_NaN());
  FitRecord fit;
  fit.point = point;
  fit.status = "invalid";
  fit.message = "run " + std::to_string(run) + ": " + std::to_string(point.kernels) +
                " kernels requested but " + std::string(shortage);
  fit.metrics = metrics.named_values();
  return fit;
}

void add_iteration_history(
    FitRecord& fit, std::span<const MetricSpec> specs,
    const std::function<void(const Eigen::VectorXd& weights, FitMetrics& metrics)>& test) {
  const auto iterations = static_cast<std::int64_t>(fit.lspi.iterates.size());
  const auto k = static_cast<std::int64_t>(fit.lspi.iterates.front().size());
  NamedArray weights{"history/weights", {iterations, k}, {}};
  weights.values.reserve(static_cast<std::size_t>(iterations * k));
  std::vector<std::vector<double>> series(specs.size());
  for (const Eigen::VectorXd& w : fit.lspi.iterates) {
    weights.values.insert(weights.values.end(), w.data(), w.data() + w.size());
    FitMetrics metrics(specs);
    test(w, metrics);
    for (std::size_t i = 0; i < specs.size(); ++i) {
      if (specs[i].tested) series[i].push_back(metrics.get(specs[i].name));
    }
  }
  fit.arrays.push_back(std::move(weights));
  for (std::size_t i = 0; i < specs.size(); ++i) {
    if (!specs[i].tested) continue;
    fit.arrays.push_back({"history/" + specs[i].name, {iterations}, std::move(series[i])});
  }
}

DatasetSpecs graph_dataset_specs() {
  static constexpr std::array kGraphDatasets = {
      DatasetSpec{"fit:laplacian_eigenvalues", "eigenvector", "1 (Laplacian eigenvalue)",
                  "basis pvf: the p smallest eigenvalues of the graph's Laplacian, ascending"},
      DatasetSpec{"fit:history/weights", "iteration,coefficient", "", "w of every iteration"},
      DatasetSpec{"fit:history/*", "iteration", "as the metric",
                  "the task's test of every iteration's greedy policy (a metric)"},
  };
  return {"graph tasks", kGraphDatasets};
}

}  // namespace ggk::engine
