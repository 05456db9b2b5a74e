#include "kernels/gaussian_kernels.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace ggk::kernels {

namespace {

void check_width(double sigma, double truncation) {
  if (!(sigma > 0.0) || !std::isfinite(sigma)) {
    throw std::invalid_argument("Gaussian kernel width sigma must be finite and > 0, got " +
                                std::to_string(sigma));
  }
  if (!(truncation >= 0.0 && truncation < 1.0)) {
    throw std::invalid_argument("kernel truncation must be in [0, 1), got " +
                                std::to_string(truncation));
  }
}

std::string number_text(double value) {
  std::ostringstream text;
  text << value;
  return text.str();
}

// Fills an N x p sparse matrix row by row from the distances distance_of(i, j),
// K = gaussian(distance), dropping values below the truncation threshold (and
// exact zeros). A NaN distance, or an infinite one where `unreachable_allowed` is
// false (Euclidean distances), throws NonFiniteKernelValue naming (i, j): without
// the check the comparison below would drop it as a zero. The entries come in row
// order, columns ascending, so they are written straight into the compressed
// arrays, sized for a dense table and cut to the entries kept (pages never written
// are never touched).
template <typename DistanceOf>
SparseRowMatrix build_kernel_matrix(Eigen::Index rows, Eigen::Index cols, double sigma,
                                    double truncation, bool unreachable_allowed,
                                    DistanceOf distance_of) {
  SparseRowMatrix matrix(rows, cols);
  matrix.resizeNonZeros(rows * cols);
  auto* outer = matrix.outerIndexPtr();
  auto* columns = matrix.innerIndexPtr();
  double* values = matrix.valuePtr();
  std::int32_t count = 0;
  outer[0] = 0;
  for (Eigen::Index i = 0; i < rows; ++i) {
    for (Eigen::Index j = 0; j < cols; ++j) {
      const double distance = distance_of(i, j);
      if (std::isnan(distance) || (std::isinf(distance) && !unreachable_allowed)) {
        throw NonFiniteKernelValue("the kernel value of state " + std::to_string(i) +
                                       " and centre " + std::to_string(j) +
                                       " is not finite: distance " + number_text(distance),
                                   i, j);
      }
      const double k = gaussian(distance, sigma);
      if (k > 0.0 && k >= truncation) {
        values[count] = k;
        columns[count] = static_cast<std::int32_t>(j);
        ++count;
      }
    }
    outer[i + 1] = count;
  }
  matrix.resizeNonZeros(count);
  return matrix;
}

// Every row of `points` finite, else NonFiniteKernelValue naming the row (as a
// state, or as a centre) and its first non-finite coordinate.
void check_finite_rows(const Eigen::Ref<const RowMatrixXd>& points, bool centres) {
  for (Eigen::Index i = 0; i < points.rows(); ++i) {
    if (points.row(i).allFinite()) continue;
    Eigen::Index coordinate = 0;
    while (std::isfinite(points(i, coordinate))) ++coordinate;
    const std::string where = std::string(centres ? "centre " : "state ") + std::to_string(i);
    throw NonFiniteKernelValue(where + " is not finite: coordinate " + std::to_string(coordinate) +
                                   " is " + number_text(points(i, coordinate)),
                               centres ? -1 : i, centres ? i : -1);
  }
}

}  // namespace

double gaussian(double distance, double sigma) {
  if (std::isinf(distance)) return 0.0;
  return std::exp(-(distance * distance) / (2.0 * sigma * sigma));
}

SparseRowMatrix ordinary_gaussian_kernels(const Eigen::Ref<const RowMatrixXd>& states,
                                          const Eigen::Ref<const RowMatrixXd>& centers,
                                          double sigma, double truncation) {
  check_width(sigma, truncation);
  if (states.cols() != centers.cols()) {
    throw std::invalid_argument("ordinary_gaussian_kernels: states have " +
                                std::to_string(states.cols()) + " dimensions, centres " +
                                std::to_string(centers.cols()));
  }
  check_finite_rows(states, false);
  check_finite_rows(centers, true);
  // Eq. (7): K(s, c) = exp(-ED(s, c)^2 / (2 sigma^2)).
  return build_kernel_matrix(
      states.rows(), centers.rows(), sigma, truncation, false,
      [&](Eigen::Index i, Eigen::Index j) { return (states.row(i) - centers.row(j)).norm(); });
}

SparseRowMatrix geodesic_gaussian_kernels(const Eigen::Ref<const RowMatrixXd>& center_distances,
                                          double sigma, double truncation) {
  check_width(sigma, truncation);
  // Eq. (8): K(s, c) = exp(-SP(s, c)^2 / (2 sigma^2)); rows of the input are centres.
  return build_kernel_matrix(
      center_distances.cols(), center_distances.rows(), sigma, truncation, true,
      [&](Eigen::Index i, Eigen::Index j) { return center_distances(j, i); });
}

SparseRowMatrix continuous_geodesic_gaussian_kernels(
    std::span<const std::int32_t> nearest_node, std::span<const double> distance_to_nearest,
    const Eigen::Ref<const RowMatrixXd>& center_distances, double sigma, double truncation) {
  check_width(sigma, truncation);
  if (nearest_node.size() != distance_to_nearest.size()) {
    throw std::invalid_argument(
        "continuous_geodesic_gaussian_kernels: nearest_node and distance_to_nearest differ in "
        "length");
  }
  for (std::size_t i = 0; i < nearest_node.size(); ++i) {
    if (nearest_node[i] < 0 || nearest_node[i] >= center_distances.cols()) {
      throw std::invalid_argument("continuous_geodesic_gaussian_kernels: state " +
                                  std::to_string(i) + " has nearest node " +
                                  std::to_string(nearest_node[i]) + " outside the graph");
    }
    if (!std::isfinite(distance_to_nearest[i])) {
      throw NonFiniteKernelValue("state " + std::to_string(i) +
                                     " is not finite: its distance to its nearest node is " +
                                     number_text(distance_to_nearest[i]),
                                 static_cast<Eigen::Index>(i), -1);
    }
  }
  // SP(s, c) = ED(s, n(s)) + SP(n(s), c) (paper sec. 4.2).
  return build_kernel_matrix(static_cast<Eigen::Index>(nearest_node.size()),
                             center_distances.rows(), sigma, truncation, true,
                             [&](Eigen::Index i, Eigen::Index j) {
                               const auto s = static_cast<std::size_t>(i);
                               return distance_to_nearest[s] + center_distances(j, nearest_node[s]);
                             });
}

SparseRowMatrix leading_columns(const SparseRowMatrix& kernels, Eigen::Index p) {
  if (p < 0 || p > kernels.cols()) {
    throw std::invalid_argument("leading_columns: " + std::to_string(p) +
                                " columns of a table of " + std::to_string(kernels.cols()));
  }
  if (!kernels.isCompressed()) {
    throw std::invalid_argument("leading_columns: the table is not compressed");
  }
  // Each row's columns ascend: its entries in the leading p columns are a prefix.
  const Eigen::Index rows = kernels.rows();
  const auto* outer = kernels.outerIndexPtr();
  const auto* columns = kernels.innerIndexPtr();
  const double* values = kernels.valuePtr();
  // Counted first: the prefix's arrays hold its entries only (a sweep keeps
  // several prefixes of one table alive at once).
  std::int64_t kept = 0;
  for (Eigen::Index i = 0; i < rows; ++i) {
    for (auto e = outer[i]; e < outer[i + 1] && columns[e] < p; ++e) ++kept;
  }
  SparseRowMatrix prefix(rows, p);
  prefix.resizeNonZeros(static_cast<Eigen::Index>(kept));
  auto* prefix_outer = prefix.outerIndexPtr();
  auto* prefix_columns = prefix.innerIndexPtr();
  double* prefix_values = prefix.valuePtr();
  std::int32_t count = 0;
  prefix_outer[0] = 0;
  for (Eigen::Index i = 0; i < rows; ++i) {
    for (auto e = outer[i]; e < outer[i + 1] && columns[e] < p; ++e) {
      prefix_values[count] = values[e];
      prefix_columns[count] = columns[e];
      ++count;
    }
    prefix_outer[i + 1] = count;
  }
  return prefix;
}

}  // namespace ggk::kernels
