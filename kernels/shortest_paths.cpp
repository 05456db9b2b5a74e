#include "kernels/shortest_paths.hpp"

#include <algorithm>
#include <bit>
#include <stdexcept>
#include <string>

#if defined(__linux__)
#include <sys/mman.h>
#endif

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
// Bucket 0 is popped from the back and rarely grows while it drains, so the next
// nodes to settle are known: their CSR offsets are prefetched kPrefetchFar pops
// ahead and their arcs and distances kPrefetchNear pops ahead. On grids larger than
// the L2 cache this hides most of the misses on the graph (measured: about a fifth
// less time on the 360 x 360 grid, none lost on the 37 x 72 one).
constexpr std::size_t kPrefetchFar = 16;
constexpr std::size_t kPrefetchNear = 8;

// A large p x N result is fresh memory from mmap, and every 4 KiB page of it
// faults on first touch. On the 2-core benchmark VM a fault costs about 20 us and
// the faults of two threads do not overlap: touching a 104 MB result (360 x 360
// grid, p = 100) took 0.4-0.7 s with 4 KiB pages at one or two threads, more than
// its 100 Dijkstras, and about 40 ms with transparent huge pages (512 times fewer
// faults). Advice only: where the kernel declines, nothing changes but the time.
void advise_huge_pages(double* data, std::size_t count) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  constexpr std::uintptr_t kHugePage = std::uintptr_t{2} << 20;
  const auto begin = reinterpret_cast<std::uintptr_t>(data);
  const std::uintptr_t end = begin + count * sizeof(double);
  const std::uintptr_t first = (begin + kHugePage - 1) & ~(kHugePage - 1);
  const std::uintptr_t last = end & ~(kHugePage - 1);
  if (last > first) madvise(reinterpret_cast<void*>(first), last - first, MADV_HUGEPAGE);
#else
  (void)data;
  (void)count;
#endif
}
}  // namespace

int DijkstraWorkspace::bucket_of(std::uint64_t key) const {
  const std::uint64_t diff = key ^ last_;
  return diff == 0 ? 0 : 64 - std::countl_zero(diff);
}

void DijkstraWorkspace::push(int bucket, std::int32_t node) {
  buckets_[static_cast<std::size_t>(bucket)].push_back(node);
  if (bucket > 0) occupied_ |= std::uint64_t{1} << (bucket - 1);
}

bool DijkstraWorkspace::refill(const double* distances) {
  while (occupied_ != 0) {
    const int bucket = std::countr_zero(occupied_) + 1;
    occupied_ &= occupied_ - 1;
    std::vector<std::int32_t>& source = buckets_[static_cast<std::size_t>(bucket)];
    // An entry is live when its node's current key still falls in this bucket
    // (keys in bucket b > 0 are above last_). Otherwise its distance dropped since
    // the push: the node is settled or waits in a lower bucket, and the entry goes.
    std::size_t live = 0;
    std::uint64_t minimum = ~std::uint64_t{0};
    const std::size_t size = source.size();
    for (std::size_t i = 0; i < size; ++i) {
      if (i + kPrefetchNear < size) __builtin_prefetch(&distances[source[i + kPrefetchNear]]);
      const std::int32_t node = source[i];
      const std::uint64_t key = key_of(distances[node]);
      if (key <= last_ || bucket_of(key) != bucket) continue;
      minimum = std::min(minimum, key);
      source[live++] = node;
    }
    if (live == 0) {
      source.clear();
      continue;
    }
    // Every live key shares with `minimum` the bits above bucket - 1, so each goes
    // to a bucket below this one; keys in higher buckets keep their bucket.
    last_ = minimum;
    for (std::size_t i = 0; i < live; ++i) {
      push(bucket_of(key_of(distances[source[i]])), source[i]);
    }
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
  for (std::vector<std::int32_t>& bucket : buckets_) bucket.clear();
  occupied_ = 0;
  last_ = 0;
  std::fill(distances.begin(), distances.end(), kUnreachable);

  const std::int64_t* indptr = graph.indptr.data();
  const std::int32_t* indices = graph.indices.data();
  const double* weights = graph.weights.data();
  double* dist = distances.data();
  std::vector<std::int32_t>& current = buckets_[0];

  // Every node in bucket 0 is live and there once: its key equals last_, and no
  // relaxation can bring a key below last_ (d(u) + w >= d(u) for w >= 0 in
  // round-to-nearest, as rounding is monotone).
  dist[source] = 0.0;
  current.push_back(source);
  while (!current.empty() || refill(dist)) {
    const std::int32_t u = current.back();
    current.pop_back();
    {
      const std::size_t size = current.size();
      if (size >= kPrefetchFar) __builtin_prefetch(&indptr[current[size - kPrefetchFar]]);
      if (size >= kPrefetchNear) {
        const std::int32_t next = current[size - kPrefetchNear];
        const std::int64_t first = indptr[next];
        __builtin_prefetch(&indices[first]);
        __builtin_prefetch(&weights[first]);
        __builtin_prefetch(&dist[next]);
      }
    }
    const double du = dist[u];
    const std::int64_t end = indptr[u + 1];
    for (std::int64_t arc = indptr[u]; arc < end; ++arc) {
      const std::int32_t v = indices[arc];
      const double candidate = du + weights[arc];
      const double old = dist[v];
      if (candidate < old) {
        dist[v] = candidate;
        // Unreached nodes (key +infinity) have no entry; a reached node keeps its
        // entry when the new key falls in the same bucket.
        const int bucket = bucket_of(key_of(candidate));
        if (old == kUnreachable || bucket != bucket_of(key_of(old))) push(bucket, v);
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
  advise_huge_pages(distances.data(), static_cast<std::size_t>(distances.size()));
  tbb::enumerable_thread_specific<DijkstraWorkspace> workspaces;
  tbb::parallel_for(std::size_t{0}, sources.size(), [&](std::size_t i) {
    std::span<double> row(distances.row(static_cast<Eigen::Index>(i)).data(),
                          static_cast<std::size_t>(graph.num_nodes));
    workspaces.local().run(graph, sources[i], row);
  });
  return distances;
}

}  // namespace ggk::kernels
