// One LSPI fit with 6,400 distinct weighted samples and k = 400 basis functions:
// a 40 x 40 grid world (1,600 states x 4 actions, one deterministic successor per
// pair, random counts as weights), 100 geodesic Gaussian centres (sigma 5,
// truncated at 1e-3), shift basis, goal in one corner.
// Also times the feature construction on its own.

#include <algorithm>

#include <benchmark/benchmark.h>

#include "bench/grid_graphs.hpp"
#include "kernels/gaussian_kernels.hpp"
#include "kernels/lspi.hpp"
#include "kernels/random_stream.hpp"
#include "kernels/shortest_paths.hpp"
#include "kernels/state_action_basis.hpp"

namespace ggk::bench {
namespace {

constexpr std::int32_t kSide = 40;
constexpr std::int32_t kActions = 4;
constexpr std::int32_t kCenters = 100;
constexpr double kSigma = 5.0;
constexpr double kTruncation = 1e-3;

struct GridProblem {
  kernels::SampleBatch samples;
  kernels::CsrGraph graph;
  std::vector<std::int32_t> centers;
};

GridProblem make_problem() {
  GridProblem problem;
  problem.graph = grid_graph(kSide, kSide);
  kernels::RandomStream rng(7, 0, 0);
  const std::int32_t goal = kSide * kSide - 1;
  for (std::int32_t s = 0; s < kSide * kSide; ++s) {
    const std::int32_t r = s / kSide, c = s % kSide;
    for (std::int32_t a = 0; a < kActions; ++a) {
      const std::int32_t nr = std::clamp(r + (a == 0 ? -1 : a == 1 ? 1 : 0), 0, kSide - 1);
      const std::int32_t nc = std::clamp(c + (a == 2 ? -1 : a == 3 ? 1 : 0), 0, kSide - 1);
      const std::int32_t next = nr * kSide + nc;
      const bool terminal = next == goal && s != goal;
      problem.samples.add(s, a, terminal ? 1.0 : 0.0, next, terminal,
                          static_cast<double>(1 + rng.uniform_index(40)));
    }
  }
  problem.centers = spread_sources(problem.graph.num_nodes, kCenters);
  return problem;
}

kernels::SparseRowMatrix make_features(const GridProblem& problem) {
  const kernels::RowMatrixXd distances =
      kernels::geodesic_distances(problem.graph, problem.centers);
  const kernels::SparseRowMatrix state_kernels =
      kernels::geodesic_gaussian_kernels(distances, kSigma, kTruncation);
  const kernels::EmpiricalTransitionModel model(
      problem.graph.num_nodes, kActions, problem.samples.states, problem.samples.actions,
      problem.samples.next_states, problem.samples.weights);
  return kernels::shift_basis(state_kernels, kActions, model);
}

void BM_BuildFeatures(benchmark::State& state) {
  const GridProblem problem = make_problem();
  for (auto _ : state) {
    kernels::SparseRowMatrix features = make_features(problem);
    benchmark::DoNotOptimize(features.valuePtr());
  }
}
BENCHMARK(BM_BuildFeatures)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_FitLspi(benchmark::State& state) {
  const GridProblem problem = make_problem();
  const kernels::SparseRowMatrix features = make_features(problem);
  kernels::LspiOptions options;
  options.solver = state.range(0) == 0 ? kernels::LspiSolver::brm : kernels::LspiSolver::lstdq;
  options.ridge = 1e-6;
  std::int64_t iterations = 0;
  for (auto _ : state) {
    const kernels::LspiResult result =
        kernels::fit_lspi(features, kActions, problem.samples, options);
    if (!result.ok()) state.SkipWithError(result.message.c_str());
    iterations = result.iterations();
    benchmark::DoNotOptimize(result.weights.data());
  }
  state.counters["lspi_iterations"] = static_cast<double>(iterations);
  state.counters["feature_nnz/row"] =
      static_cast<double>(features.nonZeros()) / static_cast<double>(features.rows());
  state.SetLabel(options.solver == kernels::LspiSolver::brm ? "brm" : "lstdq");
}
BENCHMARK(BM_FitLspi)
    ->ArgName("solver")
    ->Arg(0)
    ->Arg(1)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace
}  // namespace ggk::bench

BENCHMARK_MAIN();
