#include "kernels/gaussian_kernels.hpp"

#include <cmath>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

#include "kernels/shortest_paths.hpp"

namespace ggk::kernels {
namespace {

TEST(GaussianKernels, GaussianOfKnownDistances) {
  EXPECT_DOUBLE_EQ(gaussian(0.0, 2.0), 1.0);
  EXPECT_DOUBLE_EQ(gaussian(2.0, 2.0), std::exp(-0.5));
  EXPECT_DOUBLE_EQ(gaussian(3.0, 1.0), std::exp(-4.5));
  EXPECT_EQ(gaussian(kUnreachable, 1.0), 0.0);
}

TEST(GaussianKernels, OrdinaryKernelsUseEuclideanDistance) {
  RowMatrixXd states(2, 2), centers(2, 2);
  states << 0, 0, 3, 4;
  centers << 0, 0, 6, 8;
  const SparseRowMatrix k = ordinary_gaussian_kernels(states, centers, 5.0);
  ASSERT_EQ(k.rows(), 2);
  ASSERT_EQ(k.cols(), 2);
  EXPECT_DOUBLE_EQ(k.coeff(0, 0), 1.0);
  EXPECT_DOUBLE_EQ(k.coeff(0, 1), std::exp(-100.0 / 50.0));
  EXPECT_DOUBLE_EQ(k.coeff(1, 0), std::exp(-25.0 / 50.0));
  EXPECT_DOUBLE_EQ(k.coeff(1, 1), std::exp(-25.0 / 50.0));
}

TEST(GaussianKernels, GeodesicKernelsTransposeCentreDistancesAndZeroUnreachable) {
  RowMatrixXd center_distances(2, 3);  // 2 centres x 3 nodes
  center_distances << 0, 1, kUnreachable, 2, 0, 3;
  const SparseRowMatrix k = geodesic_gaussian_kernels(center_distances, 1.0);
  ASSERT_EQ(k.rows(), 3);
  ASSERT_EQ(k.cols(), 2);
  EXPECT_DOUBLE_EQ(k.coeff(0, 0), 1.0);
  EXPECT_DOUBLE_EQ(k.coeff(0, 1), std::exp(-2.0));
  EXPECT_DOUBLE_EQ(k.coeff(1, 0), std::exp(-0.5));
  EXPECT_EQ(k.coeff(2, 0), 0.0);
  EXPECT_DOUBLE_EQ(k.coeff(2, 1), std::exp(-4.5));
  EXPECT_EQ(k.nonZeros(), 5);  // the unreachable pair is a structural zero
}

TEST(GaussianKernels, TruncationMakesStructuralZeros) {
  RowMatrixXd center_distances(1, 4);
  center_distances << 0, 1, 2, 3;
  const SparseRowMatrix k = geodesic_gaussian_kernels(center_distances, 1.0, 0.1);
  // exp(-0.5) = 0.61 and exp(-2) = 0.135 survive, exp(-4.5) = 0.011 does not.
  EXPECT_EQ(k.nonZeros(), 3);
  EXPECT_EQ(k.coeff(3, 0), 0.0);
  EXPECT_DOUBLE_EQ(k.coeff(2, 0), std::exp(-2.0));
}

TEST(GaussianKernels, ContinuousGeodesicAddsDistanceToNearestNode) {
  RowMatrixXd center_distances(1, 2);
  center_distances << 0.0, 4.0;
  const std::vector<std::int32_t> nearest = {1, 0};
  const std::vector<double> offset = {1.0, 0.5};
  const SparseRowMatrix k =
      continuous_geodesic_gaussian_kernels(nearest, offset, center_distances, 2.0);
  EXPECT_DOUBLE_EQ(k.coeff(0, 0), std::exp(-25.0 / 8.0));
  EXPECT_DOUBLE_EQ(k.coeff(1, 0), std::exp(-0.25 / 8.0));
  const std::vector<std::int32_t> bad = {2, 0};
  EXPECT_THROW(continuous_geodesic_gaussian_kernels(bad, offset, center_distances, 2.0),
               std::invalid_argument);
}

TEST(GaussianKernels, RejectsBadWidths) {
  RowMatrixXd d = RowMatrixXd::Zero(1, 1);
  EXPECT_THROW(geodesic_gaussian_kernels(d, 0.0), std::invalid_argument);
  EXPECT_THROW(geodesic_gaussian_kernels(d, -1.0), std::invalid_argument);
  EXPECT_THROW(geodesic_gaussian_kernels(d, 1.0, 1.0), std::invalid_argument);
  RowMatrixXd s(1, 2), c(1, 3);
  s.setZero();
  c.setZero();
  EXPECT_THROW(ordinary_gaussian_kernels(s, c, 1.0), std::invalid_argument);
}

}  // namespace
}  // namespace ggk::kernels
