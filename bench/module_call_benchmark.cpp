// The C++ side of the Python module's call overhead (bench/module_call_overhead.py
// times the same calls through `import ggk` and prints both): the kernels calls the
// module makes, on the inputs the script builds, without Python in between.
//   BM_CallShortestPaths/n   a path of n nodes (unit edges), one source
//   BM_CallOrdinaryKernels/p one 2-D state against p centres on the diagonal
//   BM_CallLspi/n            a chain of n states, 2 actions, 5 Gaussian kernels, BRM

#include <vector>

#include <benchmark/benchmark.h>

#include "kernels/csr_graph.hpp"
#include "kernels/gaussian_kernels.hpp"
#include "kernels/lspi.hpp"
#include "kernels/shortest_paths.hpp"

namespace ggk::bench {
namespace {

void BM_CallShortestPaths(benchmark::State& state) {
  const auto n = static_cast<std::int32_t>(state.range(0));
  std::vector<kernels::WeightedEdge> edges;
  for (std::int32_t i = 0; i + 1 < n; ++i) edges.push_back({i, i + 1, 1.0});
  const kernels::CsrGraph graph = kernels::graph_from_edges(n, edges);
  const std::vector<std::int32_t> sources{0};
  for (auto _ : state) benchmark::DoNotOptimize(kernels::geodesic_distances(graph, sources));
}
BENCHMARK(BM_CallShortestPaths)->Arg(16)->Arg(4096)->Unit(benchmark::kMicrosecond);

void BM_CallOrdinaryKernels(benchmark::State& state) {
  const auto p = static_cast<Eigen::Index>(state.range(0));
  kernels::RowMatrixXd x(1, 2);
  x << 0.3, 0.7;
  kernels::RowMatrixXd centers(p, 2);
  for (Eigen::Index j = 0; j < p; ++j) {
    centers(j, 0) = centers(j, 1) = static_cast<double>(j) / static_cast<double>(p);
  }
  for (auto _ : state) {
    benchmark::DoNotOptimize(kernels::ordinary_gaussian_kernels(x, centers, 0.5));
  }
}
BENCHMARK(BM_CallOrdinaryKernels)->Arg(40)->Unit(benchmark::kMicrosecond);

// States 0 .. n-1 at positions i / (n - 1); action 0 left, 1 right; entering the
// last state ends the episode with reward 1; every (s, a) once.
void BM_CallLspi(benchmark::State& state) {
  const auto n = static_cast<std::int32_t>(state.range(0));
  kernels::RowMatrixXd positions(n, 1);
  for (std::int32_t i = 0; i < n; ++i) positions(i, 0) = i / static_cast<double>(n - 1);
  kernels::RowMatrixXd centers(5, 1);
  for (int j = 0; j < 5; ++j) centers(j, 0) = j / 4.0;
  const kernels::SparseRowMatrix table =
      kernels::ordinary_gaussian_kernels(positions, centers, 0.25);
  kernels::SampleBatch samples;
  for (std::int32_t s = 0; s < n; ++s) {
    for (std::int32_t a = 0; a < 2; ++a) {
      const std::int32_t next = a == 0 ? (s > 0 ? s - 1 : 0) : (s + 1 < n ? s + 1 : n - 1);
      const bool end = next == n - 1 && s != n - 1;
      samples.add(s, a, end ? 1.0 : 0.0, next, end);
    }
  }
  kernels::LspiOptions options;
  options.ridge = 1e-6;
  for (auto _ : state) {
    benchmark::DoNotOptimize(kernels::fit_lspi_copy_basis(table, 2, samples, options));
  }
}
BENCHMARK(BM_CallLspi)->Arg(20)->Arg(2000)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace ggk::bench

BENCHMARK_MAIN();
