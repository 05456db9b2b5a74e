// Multi-source Dijkstra (kernels::geodesic_distances) on grid graphs.
// Args: rows, cols, sources, threads. Counters: nodes settled per second.

#include <benchmark/benchmark.h>
#include <tbb/task_arena.h>

#include "bench/grid_graphs.hpp"
#include "kernels/shortest_paths.hpp"

namespace ggk::bench {
namespace {

void BM_GeodesicDistances(benchmark::State& state) {
  const auto rows = static_cast<std::int32_t>(state.range(0));
  const auto cols = static_cast<std::int32_t>(state.range(1));
  const auto p = static_cast<std::int32_t>(state.range(2));
  const auto threads = static_cast<int>(state.range(3));
  const kernels::CsrGraph graph = grid_graph(rows, cols);
  const std::vector<std::int32_t> sources = spread_sources(graph.num_nodes, p);
  tbb::task_arena arena(threads);
  for (auto _ : state) {
    kernels::RowMatrixXd distances;
    arena.execute([&] { distances = kernels::geodesic_distances(graph, sources); });
    benchmark::DoNotOptimize(distances.data());
  }
  state.counters["settled/s"] = benchmark::Counter(static_cast<double>(graph.num_nodes) * p,
                                                   benchmark::Counter::kIsIterationInvariantRate);
}

void grid_cases(benchmark::internal::Benchmark* b) {
  for (auto [rows, cols] : {std::pair{37, 72}, std::pair{360, 360}})
    for (int p : {16, 100, 400})
      for (int threads : {1, 2}) b->Args({rows, cols, p, threads});
}

BENCHMARK(BM_GeodesicDistances)
    ->ArgNames({"rows", "cols", "p", "threads"})
    ->Apply(grid_cases)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace
}  // namespace ggk::bench

BENCHMARK_MAIN();
