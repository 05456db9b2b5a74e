#include "kernels/nearest_visited.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace ggk::kernels {

namespace {

// Euclidean distance between the state vectors of states a and b. Every distance
// nearest_visited_states() compares or returns is this one expression, so that
// its results are those of a scan over all visited states, bit for bit.
double state_distance(const RowMatrixXd& vectors, std::int32_t a, std::int32_t b) {
  return (vectors.row(a) - vectors.row(b)).norm();
}

// A k-d tree over the visited states, for nearest-neighbour queries that give
// exactly what a scan in id order gives: the smallest computed distance, ties to
// the lowest id. A subtree is skipped only when the distance from the query to
// its splitting plane, which bounds every distance inside it from below, exceeds
// the best distance by more than any rounding of the computed distances (a
// relative 1e-9, against errors of a few ulps), so every state at the best
// distance is compared. O(n log n) to build, about O(log n) per query on grids.
class VisitedStateTree {
 public:
  VisitedStateTree(const RowMatrixXd& vectors, std::vector<std::int32_t> states)
      : vectors_(vectors), states_(std::move(states)) {
    if (!states_.empty()) build(0, static_cast<std::int32_t>(states_.size()));
  }

  // The visited state nearest to `state` and its distance; requires a non-empty tree.
  std::pair<std::int32_t, double> nearest(std::int32_t state) const {
    Best best{-1, std::numeric_limits<double>::infinity()};
    search(0, state, best);
    return {best.state, best.distance};
  }

 private:
  static constexpr std::int32_t kLeafSize = 8;
  // Rounding allowance of the pruning test (see the class comment).
  static constexpr double kPruneSlack = 1.0 - 1e-9;

  struct Node {
    std::int32_t begin = 0, end = 0;  // states_[begin, end)
    Eigen::Index axis = -1;           // -1 for a leaf
    double split = 0.0;               // left subtree: coordinate <= split; right: >= split
    std::int32_t left = -1, right = -1;
  };
  struct Best {
    std::int32_t state;
    double distance;
  };

  std::int32_t build(std::int32_t begin, std::int32_t end) {
    const auto id = static_cast<std::int32_t>(nodes_.size());
    nodes_.push_back({begin, end});
    if (end - begin <= kLeafSize) return id;
    // Split the widest coordinate at its median.
    Eigen::Index axis = 0;
    double widest = -1.0;
    for (Eigen::Index k = 0; k < vectors_.cols(); ++k) {
      double lo = std::numeric_limits<double>::infinity(), hi = -lo;
      for (std::int32_t i = begin; i < end; ++i) {
        const double x = vectors_(states_[static_cast<std::size_t>(i)], k);
        lo = std::min(lo, x);
        hi = std::max(hi, x);
      }
      if (hi - lo > widest) {
        widest = hi - lo;
        axis = k;
      }
    }
    if (!(widest > 0.0)) return id;  // all equal along every axis: one leaf
    const std::int32_t mid = begin + (end - begin) / 2;
    const auto first = states_.begin() + begin;
    std::nth_element(
        first, states_.begin() + mid, states_.begin() + end,
        [&](std::int32_t a, std::int32_t b) { return vectors_(a, axis) < vectors_(b, axis); });
    const double split = vectors_(states_[static_cast<std::size_t>(mid)], axis);
    const std::int32_t left = build(begin, mid);
    const std::int32_t right = build(mid, end);
    Node& node = nodes_[static_cast<std::size_t>(id)];
    node.axis = axis;
    node.split = split;
    node.left = left;
    node.right = right;
    return id;
  }

  void search(std::int32_t id, std::int32_t query, Best& best) const {
    const Node& node = nodes_[static_cast<std::size_t>(id)];
    if (node.axis < 0) {
      for (std::int32_t i = node.begin; i < node.end; ++i) {
        const std::int32_t v = states_[static_cast<std::size_t>(i)];
        const double d = state_distance(vectors_, query, v);
        if (d < best.distance || (d == best.distance && v < best.state)) best = {v, d};
      }
      return;
    }
    const double offset = vectors_(query, node.axis) - node.split;
    const std::int32_t near = offset <= 0.0 ? node.left : node.right;
    const std::int32_t far = offset <= 0.0 ? node.right : node.left;
    search(near, query, best);
    if (std::abs(offset) * kPruneSlack <= best.distance) search(far, query, best);
  }

  const RowMatrixXd& vectors_;
  std::vector<std::int32_t> states_;  // the visited states, permuted into the tree's leaves
  std::vector<Node> nodes_;           // nodes_[0] is the root
};

}  // namespace

void nearest_visited_states(const RowMatrixXd& state_vectors,
                            const std::vector<std::uint8_t>& visited,
                            std::vector<std::int32_t>& nearest, std::vector<double>& distance) {
  const auto n = static_cast<std::int32_t>(state_vectors.rows());
  nearest.assign(static_cast<std::size_t>(n), 0);
  distance.assign(static_cast<std::size_t>(n), 0.0);
  std::vector<std::int32_t> visited_states;
  for (std::int32_t s = 0; s < n; ++s) {
    if (visited[static_cast<std::size_t>(s)]) {
      nearest[static_cast<std::size_t>(s)] = s;
      visited_states.push_back(s);
    }
  }
  if (visited_states.empty()) {
    std::fill(distance.begin(), distance.end(), std::numeric_limits<double>::infinity());
    return;
  }
  const VisitedStateTree tree(state_vectors, std::move(visited_states));
  tbb::parallel_for(tbb::blocked_range<std::int32_t>(0, n, 1024),
                    [&](const tbb::blocked_range<std::int32_t>& range) {
                      for (std::int32_t s = range.begin(); s < range.end(); ++s) {
                        if (visited[static_cast<std::size_t>(s)]) continue;
                        const auto [v, d] = tree.nearest(s);
                        nearest[static_cast<std::size_t>(s)] = v;
                        distance[static_cast<std::size_t>(s)] = d;
                      }
                    });
}

}  // namespace ggk::kernels
