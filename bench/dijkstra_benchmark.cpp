// Multi-source Dijkstra (kernels::geodesic_distances) on grid graphs.
// Args: rows, cols, sources, threads. Counters: nodes settled per second.

#include <benchmark/benchmark.h>
#include <tbb/task_arena.h>

#include "bench/geodesic_distances_case.hpp"

namespace ggk::bench {
namespace {

void BM_GeodesicDistances(benchmark::State& state) {
  time_geodesic_distances(state, static_cast<int>(state.range(3)));
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
