// The graph-protocol layer (engine/tasks/graph_protocol.hpp): metrics by name in
// declared order, the invalid fit's record, the run's graph on a path graph with
// known distances and diagnostics, and the iteration history of the tested
// metrics only.

#include "engine/tasks/graph_protocol.hpp"

#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "kernels/csr_graph.hpp"

namespace ggk::engine {
namespace {

const std::vector<MetricSpec> kSpecs = {tested(fraction_metric("score", "a share")),
                                        mean_metric("lspi_iterations", "iterations", ""),
                                        tested(mean_metric("steps", "steps", ""))};

TEST(FitMetrics, SetByNameInDeclaredOrderTheRestNaN) {
  FitMetrics metrics(kSpecs);
  metrics.set("steps", 3.0);
  metrics.set("score", 0.5);
  const auto values = metrics.named_values();
  ASSERT_EQ(values.size(), 3u);
  EXPECT_EQ(values[0].first, "score");
  EXPECT_EQ(values[0].second, 0.5);
  EXPECT_EQ(values[1].first, "lspi_iterations");
  EXPECT_TRUE(std::isnan(values[1].second));
  EXPECT_EQ(values[2].second, 3.0);
  EXPECT_EQ(metrics.get("steps"), 3.0);
  EXPECT_THROW(metrics.set("success_rate", 1.0), std::logic_error);
}

TEST(FitMetrics, DeclaredKinds) {
  EXPECT_EQ(declared_kind(kSpecs, "score"), MetricKind::kFraction);
  EXPECT_EQ(declared_kind(kSpecs, "steps"), MetricKind::kMean);
  EXPECT_EQ(declared_kind(kSpecs, "undeclared"), MetricKind::kMean);
  for (const MetricSpec& spec : graph_metric_specs()) {
    EXPECT_FALSE(spec.tested) << spec.name;
    EXPECT_EQ(spec.kind, MetricKind::kMean) << spec.name;
  }
}

// 0 - 1 - 2 - 3 on a line, unit steps; node 3 is not a graph node of the run.
kernels::CsrGraph path_graph() {
  kernels::RowMatrixXd vectors(4, 1);
  vectors << 0.0, 1.0, 2.0, 3.0;
  const std::vector<kernels::NodeTransition> moves = {{0, 1}, {1, 2}};
  return kernels::transition_graph(vectors, moves);
}

TEST(RunGraph, DistancesFromTheCentresTheLargestFitUsesAndDiagnostics) {
  kernels::RowMatrixXd vectors(4, 1);
  vectors << 0.0, 1.0, 2.0, 3.0;
  const std::vector<std::uint8_t> is_node = {1, 1, 1, 0};
  SweepPoint small, large;
  small.kernels = 1;
  large.kernels = 2;
  const std::vector<SweepPoint> points = {small, large};
  const RunGraph graph = run_graph(path_graph(), is_node, {2, 0, 1}, vectors, points);
  EXPECT_EQ(graph.nodes, 3);
  EXPECT_EQ(graph.centers, (std::vector<std::int32_t>{2, 0, 1}));
  ASSERT_EQ(graph.center_distances.rows(), 2);  // the largest kernel count
  EXPECT_EQ(graph.center_distances(0, 0), 2.0);
  EXPECT_EQ(graph.center_distances(1, 2), 2.0);
  EXPECT_TRUE(std::isinf(graph.center_distances(0, 3)));
  EXPECT_EQ(graph.edges, 2.0);
  EXPECT_EQ(graph.median_degree, 1.0);     // degrees 1, 2, 1
  EXPECT_EQ(graph.geodesic_stretch, 1.0);  // a line: SP = ED

  std::vector<MetricSpec> specs = {kSpecs[0]};
  specs.insert(specs.end(), graph_metric_specs().begin(), graph_metric_specs().end());
  FitMetrics metrics(specs);
  metrics.set("lspi_iterations", 0.0);
  set_graph_metrics(metrics, graph, 0.25);
  EXPECT_EQ(metrics.get("graph_nodes"), 3.0);
  EXPECT_EQ(metrics.get("kernel_gap"), 0.25);

  SweepPoint too_many;
  too_many.kernels = 5;
  const FitRecord fit = invalid_fit(too_many, 7, graph, specs, "the sample graph has only 3 nodes");
  EXPECT_EQ(fit.status, "invalid");
  EXPECT_EQ(fit.message, "run 7: 5 kernels requested but the sample graph has only 3 nodes");
  EXPECT_EQ(fit.point.kernels, 5);
  ASSERT_EQ(fit.metrics.size(), specs.size());
  EXPECT_EQ(fit.metrics[0].first, "score");
  EXPECT_TRUE(std::isnan(fit.metrics[0].second));
  EXPECT_EQ(fit.metrics[1], (std::pair<std::string, double>{"lspi_iterations", 0.0}));
  EXPECT_EQ(fit.metrics[2], (std::pair<std::string, double>{"graph_nodes", 3.0}));
  EXPECT_EQ(fit.metrics.back().first, "kernel_gap");
  EXPECT_TRUE(std::isnan(fit.metrics.back().second));
  EXPECT_TRUE(fit.centers.empty());
}

TEST(IterationHistory, WeightsAndEveryTestedMetricPerIterate) {
  FitRecord fit;
  fit.lspi.iterates = {Eigen::Vector2d(1.0, 2.0), Eigen::Vector2d(3.0, 4.0)};
  add_iteration_history(fit, kSpecs, [](const Eigen::VectorXd& w, FitMetrics& metrics) {
    metrics.set("score", w(0));
    metrics.set("steps", w(1));
  });
  ASSERT_EQ(fit.arrays.size(), 3u);  // weights, score, steps: not lspi_iterations
  EXPECT_EQ(fit.arrays[0].name, "history/weights");
  EXPECT_EQ(fit.arrays[0].shape, (std::vector<std::int64_t>{2, 2}));
  EXPECT_EQ(fit.arrays[0].values, (std::vector<double>{1.0, 2.0, 3.0, 4.0}));
  EXPECT_EQ(fit.arrays[1].name, "history/score");
  EXPECT_EQ(fit.arrays[1].values, (std::vector<double>{1.0, 3.0}));
  EXPECT_EQ(fit.arrays[2].name, "history/steps");
  EXPECT_EQ(fit.arrays[2].values, (std::vector<double>{2.0, 4.0}));
}

}  // namespace
}  // namespace ggk::engine
