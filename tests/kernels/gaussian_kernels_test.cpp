#include "kernels/gaussian_kernels.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
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

// The state and centre a refused kernel value names, and its message.
struct Refusal {
  Eigen::Index state = -2;
  Eigen::Index centre = -2;
  std::string message;
};

template <typename Call>
Refusal refusal_of(Call call) {
  try {
    call();
  } catch (const NonFiniteKernelValue& e) {
    return {e.state(), e.centre(), e.what()};
  }
  return {};
}

// A NaN once dropped out of the table as a zero (the truncation test is false for
// NaN); now the value is refused, naming its state and centre.
TEST(GaussianKernels, NonFiniteValuesAreRefusedNamingStateAndCentre) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  RowMatrixXd states(3, 2), centers(2, 2);
  states << 0, 0, 1, nan, 2, 2;
  centers << 0, 0, 1, 1;
  Refusal r = refusal_of([&] { ordinary_gaussian_kernels(states, centers, 1.0); });
  EXPECT_EQ(r.state, 1);
  EXPECT_EQ(r.centre, -1);
  EXPECT_NE(r.message.find("state 1 is not finite: coordinate 1 is nan"), std::string::npos)
      << r.message;
  states(1, 1) = 1.0;
  centers(1, 0) = -inf;
  r = refusal_of([&] { ordinary_gaussian_kernels(states, centers, 1.0); });
  EXPECT_EQ(r.state, -1);
  EXPECT_EQ(r.centre, 1);
  EXPECT_NE(r.message.find("centre 1 is not finite: coordinate 0 is -inf"), std::string::npos)
      << r.message;

  // A NaN shortest-path distance; +inf (unreachable) stays a zero.
  RowMatrixXd center_distances(2, 3);  // 2 centres x 3 nodes
  center_distances << 0, 1, kUnreachable, 2, nan, 3;
  r = refusal_of([&] { geodesic_gaussian_kernels(center_distances, 1.0, 0.1); });
  EXPECT_EQ(r.state, 1);
  EXPECT_EQ(r.centre, 1);
  EXPECT_NE(r.message.find("kernel value of state 1 and centre 1 is not finite: distance nan"),
            std::string::npos)
      << r.message;

  const std::vector<std::int32_t> nearest = {1, 0, 2};
  r = refusal_of([&] {
    continuous_geodesic_gaussian_kernels(nearest, std::vector<double>{0.5, 0.0, 0.0},
                                         center_distances, 1.0);
  });
  EXPECT_EQ(r.state, 0);
  EXPECT_EQ(r.centre, 1);
  for (const double bad : {nan, inf}) {
    r = refusal_of([&] {
      continuous_geodesic_gaussian_kernels(nearest, std::vector<double>{0.5, bad, 0.0},
                                           center_distances.topRows(1), 1.0);
    });
    EXPECT_EQ(r.state, 1) << bad;
    EXPECT_EQ(r.centre, -1) << bad;
    EXPECT_NE(r.message.find("distance to its nearest node"), std::string::npos) << r.message;
  }
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

// The leading p columns of a table of more centres are the table of the first p
// centres bit for bit, for the three builders, with truncation (rows whose kept
// entries end before p, and rows with none) and without; bad counts are refused.
TEST(GaussianKernels, LeadingColumnsAreTheTableOfTheFirstCentres) {
  RowMatrixXd states(60, 3), centers(12, 3);
  for (Eigen::Index i = 0; i < states.rows(); ++i) {
    const auto x = static_cast<double>(i);
    states.row(i) << std::sin(0.7 * x), std::cos(1.3 * x), 0.05 * x;
  }
  for (Eigen::Index j = 0; j < centers.rows(); ++j) {
    const auto x = static_cast<double>(j);
    centers.row(j) << std::cos(2.1 * x), std::sin(0.4 * x), 0.25 * x;
  }
  RowMatrixXd center_distances(12, 20);
  for (Eigen::Index j = 0; j < 12; ++j) {
    for (Eigen::Index n = 0; n < 20; ++n) {
      center_distances(j, n) = j == n + 1 ? std::numeric_limits<double>::infinity()
                                          : std::abs(static_cast<double>(j - n)) * 0.8;
    }
  }
  std::vector<std::int32_t> nearest(60);
  std::vector<double> to_nearest(60);
  for (std::size_t i = 0; i < 60; ++i) {
    nearest[i] = static_cast<std::int32_t>((7 * i) % 20);
    to_nearest[i] = 0.01 * static_cast<double>(i);
  }
  for (const double truncation : {0.0, 0.3}) {
    const SparseRowMatrix all_ogk = ordinary_gaussian_kernels(states, centers, 0.9, truncation);
    const SparseRowMatrix all_ggk = geodesic_gaussian_kernels(center_distances, 1.5, truncation);
    const SparseRowMatrix all_continuous = continuous_geodesic_gaussian_kernels(
        nearest, to_nearest, center_distances, 1.5, truncation);
    for (const Eigen::Index p :
         {Eigen::Index{0}, Eigen::Index{1}, Eigen::Index{5}, Eigen::Index{12}}) {
      const SparseRowMatrix ogk = leading_columns(all_ogk, p);
      const SparseRowMatrix expected_ogk =
          ordinary_gaussian_kernels(states, centers.topRows(p), 0.9, truncation);
      ASSERT_EQ(ogk.cols(), p);
      EXPECT_EQ(ogk.nonZeros(), expected_ogk.nonZeros());
      EXPECT_EQ(Eigen::MatrixXd(ogk), Eigen::MatrixXd(expected_ogk)) << p;
      EXPECT_EQ(
          Eigen::MatrixXd(leading_columns(all_ggk, p)),
          Eigen::MatrixXd(geodesic_gaussian_kernels(center_distances.topRows(p), 1.5, truncation)))
          << p;
      const SparseRowMatrix continuous = leading_columns(all_continuous, p);
      const SparseRowMatrix expected_continuous = continuous_geodesic_gaussian_kernels(
          nearest, to_nearest, center_distances.topRows(p), 1.5, truncation);
      EXPECT_EQ(continuous.nonZeros(), expected_continuous.nonZeros());
      EXPECT_EQ(Eigen::MatrixXd(continuous), Eigen::MatrixXd(expected_continuous)) << p;
    }
    if (truncation > 0.0) {
      EXPECT_LT(all_ogk.nonZeros(), 60 * 12);  // the test meets truncation
    }
  }
  const SparseRowMatrix all = ordinary_gaussian_kernels(states, centers, 0.9);
  EXPECT_THROW(leading_columns(all, 13), std::invalid_argument);
  EXPECT_THROW(leading_columns(all, -1), std::invalid_argument);
  SparseRowMatrix uncompressed = all;
  uncompressed.uncompress();
  EXPECT_THROW(leading_columns(uncompressed, 3), std::invalid_argument);
}

}  // namespace
}  // namespace ggk::kernels
