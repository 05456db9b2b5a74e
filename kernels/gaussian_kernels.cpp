#include "kernels/gaussian_kernels.hpp"

#include <cmath>
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

// Fills an N x p sparse matrix row by row from kernel_of(i, j), dropping values
// below the truncation threshold (and exact zeros). The entries come in row order,
// columns ascending, so they are written straight into the compressed arrays,
// sized for a dense table and cut to the entries kept (pages never written are
// never touched).
template <typename KernelOf>
SparseRowMatrix build_kernel_matrix(Eigen::Index rows, Eigen::Index cols, double truncation,
                                    KernelOf kernel_of) {
  SparseRowMatrix matrix(rows, cols);
  matrix.resizeNonZeros(rows * cols);
  auto* outer = matrix.outerIndexPtr();
  auto* columns = matrix.innerIndexPtr();
  double* values = matrix.valuePtr();
  std::int32_t count = 0;
  outer[0] = 0;
  for (Eigen::Index i = 0; i < rows; ++i) {
    for (Eigen::Index j = 0; j < cols; ++j) {
      const double k = kernel_of(i, j);
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
  // Eq. (7): K(s, c) = exp(-ED(s, c)^2 / (2 sigma^2)).
  return build_kernel_matrix(states.rows(), centers.rows(), truncation,
                             [&](Eigen::Index i, Eigen::Index j) {
                               return gaussian((states.row(i) - centers.row(j)).norm(), sigma);
                             });
}

SparseRowMatrix geodesic_gaussian_kernels(const Eigen::Ref<const RowMatrixXd>& center_distances,
                                          double sigma, double truncation) {
  check_width(sigma, truncation);
  // Eq. (8): K(s, c) = exp(-SP(s, c)^2 / (2 sigma^2)); rows of the input are centres.
  return build_kernel_matrix(
      center_distances.cols(), center_distances.rows(), truncation,
      [&](Eigen::Index i, Eigen::Index j) { return gaussian(center_distances(j, i), sigma); });
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
  }
  // SP(s, c) = ED(s, n(s)) + SP(n(s), c) (paper sec. 4.2).
  return build_kernel_matrix(
      static_cast<Eigen::Index>(nearest_node.size()), center_distances.rows(), truncation,
      [&](Eigen::Index i, Eigen::Index j) {
        const auto s = static_cast<std::size_t>(i);
        return gaussian(distance_to_nearest[s] + center_distances(j, nearest_node[s]), sigma);
      });
}

}  // namespace ggk::kernels
