#pragma once
// One timed case of kernels::geodesic_distances on a grid graph, shared by
// dijkstra_benchmark (over threads) and boost_dijkstra_benchmark (at one thread,
// beside Boost.Graph in the same executable). Args rows, cols, p from
// state.range(0..2). Counter: nodes settled per second.

#include <cstdint>
#include <vector>

#include <benchmark/benchmark.h>
#include <tbb/task_arena.h>

#include "bench/grid_graphs.hpp"
#include "kernels/shortest_paths.hpp"

namespace ggk::bench {

inline void time_geodesic_distances(benchmark::State& state, int threads) {
  const auto rows = static_cast<std::int32_t>(state.range(0));
  const auto cols = static_cast<std::int32_t>(state.range(1));
  const auto p = static_cast<std::int32_t>(state.range(2));
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

}  // namespace ggk::bench
