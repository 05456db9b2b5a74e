#include "kernels/graph_diagnostics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

#include "kernels/gaussian_kernels.hpp"

namespace ggk::kernels {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// The median of `values` (reordered): the middle value, or the mean of the two
// middle values for an even count; NaN when empty.
double median(std::vector<double>& values) {
  if (values.empty()) return kNaN;
  const std::size_t mid = values.size() / 2;
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(mid), values.end());
  const double upper = values[mid];
  if (values.size() % 2 == 1) return upper;
  const double lower =
      *std::max_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(mid));
  return 0.5 * (lower + upper);
}

bool has_arc(const CsrGraph& graph, std::int32_t from, std::int32_t to) {
  const auto heads = graph.neighbors(from);
  return std::binary_search(heads.begin(), heads.end(), to);
}

}  // namespace

std::int64_t undirected_edge_count(const CsrGraph& graph) {
  std::int64_t edges = 0;
  for (std::int32_t u = 0; u < graph.num_nodes; ++u) {
    for (std::int32_t v : graph.neighbors(u)) {
      // Each pair once: from its smaller end, or from the larger end when the
      // arc back is missing (a directed graph).
      if (u < v || (v < u && !has_arc(graph, v, u))) ++edges;
    }
  }
  return edges;
}

double median_degree(const CsrGraph& graph, std::span<const std::uint8_t> is_node) {
  if (is_node.size() != static_cast<std::size_t>(graph.num_nodes)) {
    throw std::invalid_argument("median_degree: one flag per node expected");
  }
  std::vector<double> degrees;
  for (std::int32_t u = 0; u < graph.num_nodes; ++u) {
    if (is_node[static_cast<std::size_t>(u)]) {
      degrees.push_back(static_cast<double>(graph.neighbors(u).size()));
    }
  }
  return median(degrees);
}

double geodesic_stretch(const Eigen::Ref<const RowMatrixXd>& center_distances,
                        std::span<const std::int32_t> centers,
                        const Eigen::Ref<const RowMatrixXd>& node_states) {
  if (center_distances.rows() < static_cast<Eigen::Index>(centers.size())) {
    throw std::invalid_argument("geodesic_stretch: one distance row per centre expected");
  }
  std::vector<double> ratios;
  for (std::size_t i = 0; i < centers.size(); ++i) {
    for (std::size_t j = i + 1; j < centers.size(); ++j) {
      const double sp = center_distances(static_cast<Eigen::Index>(i), centers[j]);
      const double ed = (node_states.row(centers[i]) - node_states.row(centers[j])).norm();
      if (std::isfinite(sp) && ed > 0.0) ratios.push_back(sp / ed);
    }
  }
  return median(ratios);
}

double kernel_gap_sum(std::span<const double> geodesic, std::span<const double> euclidean,
                      double sigma) {
  if (geodesic.size() != euclidean.size()) {
    throw std::invalid_argument("kernel_gap_sum: one Euclidean distance per geodesic one");
  }
  double sum = 0.0;
  for (std::size_t i = 0; i < geodesic.size(); ++i) {
    sum += std::abs(gaussian(geodesic[i], sigma) - gaussian(euclidean[i], sigma));
  }
  return sum;
}

}  // namespace ggk::kernels
