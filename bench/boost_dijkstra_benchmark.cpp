// Peer comparison: Boost.Graph's dijkstra_shortest_paths (a field-standard
// implementation) on the same grid graphs and sources as dijkstra_benchmark's
// BM_GeodesicDistances with one thread. Args: rows, cols, sources. Before timing,
// each case checks that Boost's distances equal kernels::geodesic_distances bit
// for bit (the benchmark reports an error otherwise). BM_GeodesicDistancesBesideBoost
// times geodesic_distances in a one-thread arena on the same cases, so that one run
// of this executable, best with --benchmark_enable_random_interleaving=true on a
// shared machine, gives the ratio.

#include <boost/graph/compressed_sparse_row_graph.hpp>
#include <boost/graph/dijkstra_shortest_paths.hpp>
#include <boost/property_map/property_map.hpp>

#include <cstring>
#include <utility>
#include <vector>

#include <benchmark/benchmark.h>
#include <tbb/task_arena.h>

#include "bench/geodesic_distances_case.hpp"
#include "bench/grid_graphs.hpp"
#include "kernels/shortest_paths.hpp"

namespace ggk::bench {
namespace {

struct EdgeWeight {
  double weight;
};
using BoostGraph =
    boost::compressed_sparse_row_graph<boost::directedS, boost::no_property, EdgeWeight>;

BoostGraph to_boost(const kernels::CsrGraph& graph) {
  std::vector<std::pair<std::int32_t, std::int32_t>> arcs;
  std::vector<EdgeWeight> weights;
  for (std::int32_t u = 0; u < graph.num_nodes; ++u) {
    for (std::int64_t a = graph.indptr[u]; a < graph.indptr[u + 1]; ++a) {
      arcs.emplace_back(u, graph.indices[a]);
      weights.push_back({graph.weights[a]});
    }
  }
  return BoostGraph(boost::edges_are_sorted, arcs.begin(), arcs.end(), weights.begin(),
                    static_cast<std::size_t>(graph.num_nodes));
}

void BM_BoostGraphDijkstra(benchmark::State& state) {
  const auto rows = static_cast<std::int32_t>(state.range(0));
  const auto cols = static_cast<std::int32_t>(state.range(1));
  const auto p = static_cast<std::int32_t>(state.range(2));
  const kernels::CsrGraph csr = grid_graph(rows, cols);
  const BoostGraph graph = to_boost(csr);
  const std::vector<std::int32_t> sources = spread_sources(csr.num_nodes, p);
  std::vector<double> distances(static_cast<std::size_t>(csr.num_nodes));
  auto boost_dijkstra = [&](std::int32_t source) {
    boost::dijkstra_shortest_paths(
        graph, static_cast<std::size_t>(source),
        boost::distance_map(boost::make_iterator_property_map(
                                distances.begin(), boost::get(boost::vertex_index, graph)))
            .weight_map(boost::get(&EdgeWeight::weight, graph)));
  };
  const kernels::RowMatrixXd ggk = kernels::geodesic_distances(csr, sources);
  for (std::size_t i = 0; i < sources.size(); ++i) {
    boost_dijkstra(sources[i]);
    if (std::memcmp(distances.data(), ggk.row(static_cast<Eigen::Index>(i)).data(),
                    sizeof(double) * distances.size()) != 0) {
      state.SkipWithError("Boost.Graph and geodesic_distances differ");
      return;
    }
  }
  for (auto _ : state) {
    for (std::int32_t source : sources) {
      boost_dijkstra(source);
      benchmark::DoNotOptimize(distances.data());
    }
  }
  state.counters["settled/s"] = benchmark::Counter(static_cast<double>(csr.num_nodes) * p,
                                                   benchmark::Counter::kIsIterationInvariantRate);
}

void BM_GeodesicDistancesBesideBoost(benchmark::State& state) {
  time_geodesic_distances(state, 1);
}

void peer_cases(benchmark::internal::Benchmark* b) {
  b->ArgNames({"rows", "cols", "p"})
      ->Args({37, 72, 100})
      ->Args({360, 360, 16})
      ->Unit(benchmark::kMillisecond)
      ->UseRealTime();
}

BENCHMARK(BM_BoostGraphDijkstra)->Apply(peer_cases);
BENCHMARK(BM_GeodesicDistancesBesideBoost)->Apply(peer_cases);

}  // namespace
}  // namespace ggk::bench

BENCHMARK_MAIN();
