#include "kernels/shortest_paths.hpp"

#include <algorithm>
#include <bit>
#include <stdexcept>
#include <string>

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

namespace ggk::kernels {

namespace {
// Non-negative doubles (+0.0 up to +infinity) order like their IEEE bit patterns
// read as unsigned integers. Distances are never -0.0: the source starts at +0.0
// and +0.0 + w is +0.0 for w = -0.0.
std::uint64_t key_of(double distance) {
  return std::bit_cast<std::uint64_t>(distance);
}
}  // namespace

void DijkstraWorkspace::push(std::uint64_t key, std::int32_t node) {
  // Keys pushed are never below last_: d(u) + w >= d(u) = last_ for w >= 0 in
  // round-to-nearest, as rounding is monotone.
  const std::uint64_t diff = key ^ last_;
  const int bucket = diff == 0 ? 0 : 64 - std::countl_zero(diff);
  buckets_[static_cast<std::size_t>(bucket)].push_back({key, node});
  if (bucket > 0) occupied_ |= std::uint64_t{1} << (bucket - 1);
}

bool DijkstraWorkspace::refill(std::span<const double> distances) {
  while (occupied_ != 0) {
    const int bucket = std::countr_zero(occupied_) + 1;
    occupied_ &= occupied_ - 1;
    std::vector<Entry>& source = buckets_[static_cast<std::size_t>(bucket)];
    // Drop stale entries (the node has since been pushed with a smaller key) and
    // find the minimum of the live ones.
    std::size_t live = 0;
    std::uint64_t minimum = ~std::uint64_t{0};
    for (const Entry& e : source) {
      if (e.key != key_of(distances[static_cast<std::size_t>(e.node)])) continue;
      minimum = std::min(minimum, e.key);
      source[live++] = e;
    }
    if (live == 0) {
      source.clear();
      continue;
    }
    // Every live key shares with `minimum` the bits above bucket-1, so each goes
    // to a bucket below this one; keys in higher buckets keep their bucket.
    last_ = minimum;
    for (std::size_t i = 0; i < live; ++i) push(source[i].key, source[i].node);
    source.clear();
    return true;
  }
  return false;
}

void DijkstraWorkspace::run(const CsrGraph& graph, std::int32_t source,
                            std::span<double> distances) {
  const auto n = static_cast<std::size_t>(graph.num_nodes);
  if (distances.size() != n) {
    throw std::invalid_argument("shortest_path_distances: distance buffer has " +
                                std::to_string(distances.size()) + " entries, graph has " +
                                std::to_string(n) + " nodes");
  }
  if (source < 0 || source >= graph.num_nodes) {
    throw std::invalid_argument("shortest_path_distances: source " + std::to_string(source) +
                                " outside [0, " + std::to_string(n) + ")");
  }
  for (std::vector<Entry>& bucket : buckets_) bucket.clear();
  occupied_ = 0;
  last_ = 0;
  std::fill(distances.begin(), distances.end(), kUnreachable);

  const std::int64_t* indptr = graph.indptr.data();
  const std::int32_t* indices = graph.indices.data();
  const double* weights = graph.weights.data();
  double* dist = distances.data();
  std::vector<Entry>& current = buckets_[0];

  dist[source] = 0.0;
  current.push_back({key_of(0.0), source});
  for (;;) {
    if (current.empty() && !refill(distances)) break;
    const Entry top = current.back();
    current.pop_back();
    const auto u = static_cast<std::size_t>(top.node);
    // A stale entry: the node was pushed again with a smaller key and is settled.
    if (top.key != key_of(dist[u])) continue;
    const double du = dist[u];
    const std::int64_t end = indptr[u + 1];
    for (std::int64_t arc = indptr[u]; arc < end; ++arc) {
      const std::int32_t v = indices[arc];
      const double candidate = du + weights[arc];
      if (candidate < dist[v]) {
        dist[v] = candidate;
        push(key_of(candidate), v);
      }
    }
  }
}

void shortest_path_distances(const CsrGraph& graph, std::int32_t source,
                             std::span<double> distances, DijkstraWorkspace& workspace) {
  workspace.run(graph, source, distances);
}

RowMatrixXd geodesic_distances(const CsrGraph& graph, std::span<const std::int32_t> sources) {
  for (std::size_t i = 0; i < sources.size(); ++i) {
    if (sources[i] < 0 || sources[i] >= graph.num_nodes) {
      throw std::invalid_argument("geodesic_distances: source " + std::to_string(i) + " (node " +
                                  std::to_string(sources[i]) + ") outside [0, " +
                                  std::to_string(graph.num_nodes) + ")");
    }
  }
  RowMatrixXd distances(static_cast<Eigen::Index>(sources.size()), graph.num_nodes);
  tbb::enumerable_thread_specific<DijkstraWorkspace> workspaces;
  tbb::parallel_for(std::size_t{0}, sources.size(), [&](std::size_t i) {
    std::span<double> row(distances.row(static_cast<Eigen::Index>(i)).data(),
                          static_cast<std::size_t>(graph.num_nodes));
    workspaces.local().run(graph, sources[i], row);
  });
  return distances;
}

}  // namespace ggk::kernels
