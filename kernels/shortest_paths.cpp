#include "kernels/shortest_paths.hpp"

#include <stdexcept>
#include <string>

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

namespace ggk::kernels {

namespace {
constexpr std::size_t kArity = 4;  // 4-ary heap: shallower than binary, children share a cache line
}

void DijkstraWorkspace::sift_up(std::size_t slot, std::span<const double> distances) {
  const std::int32_t node = heap_[slot];
  const double key = distances[node];
  while (slot > 0) {
    const std::size_t parent = (slot - 1) / kArity;
    const std::int32_t parent_node = heap_[parent];
    if (distances[parent_node] <= key) break;
    heap_[slot] = parent_node;
    position_[parent_node] = static_cast<std::int32_t>(slot);
    slot = parent;
  }
  heap_[slot] = node;
  position_[node] = static_cast<std::int32_t>(slot);
}

void DijkstraWorkspace::sift_down(std::size_t slot, std::span<const double> distances) {
  const std::size_t size = heap_.size();
  const std::int32_t node = heap_[slot];
  const double key = distances[node];
  for (;;) {
    const std::size_t first = slot * kArity + 1;
    if (first >= size) break;
    const std::size_t last = std::min(first + kArity, size);
    std::size_t best = first;
    double best_key = distances[heap_[first]];
    for (std::size_t c = first + 1; c < last; ++c) {
      const double k = distances[heap_[c]];
      if (k < best_key) {
        best = c;
        best_key = k;
      }
    }
    if (best_key >= key) break;
    heap_[slot] = heap_[best];
    position_[heap_[slot]] = static_cast<std::int32_t>(slot);
    slot = best;
  }
  heap_[slot] = node;
  position_[node] = static_cast<std::int32_t>(slot);
}

void DijkstraWorkspace::push_or_decrease(std::int32_t node, std::span<const double> distances) {
  std::int32_t slot = position_[node];
  if (slot < 0) {
    slot = static_cast<std::int32_t>(heap_.size());
    heap_.push_back(node);  // capacity reserved in run(): never reallocates
  }
  sift_up(static_cast<std::size_t>(slot), distances);
}

std::int32_t DijkstraWorkspace::pop_min(std::span<const double> distances) {
  const std::int32_t top = heap_.front();
  position_[top] = -1;
  const std::int32_t last = heap_.back();
  heap_.pop_back();
  if (!heap_.empty()) {
    heap_.front() = last;
    sift_down(0, distances);
  }
  return top;
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
  if (position_.size() < n) position_.assign(n, -1);
  heap_.clear();
  heap_.reserve(n);
  std::fill(distances.begin(), distances.end(), kUnreachable);

  distances[source] = 0.0;
  push_or_decrease(source, distances);
  while (!heap_.empty()) {
    const std::int32_t u = pop_min(distances);
    const double du = distances[u];
    const std::int64_t end = graph.indptr[u + 1];
    for (std::int64_t arc = graph.indptr[u]; arc < end; ++arc) {
      const std::int32_t v = graph.indices[arc];
      const double candidate = du + graph.weights[arc];
      if (candidate < distances[v]) {
        distances[v] = candidate;
        push_or_decrease(v, distances);
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
