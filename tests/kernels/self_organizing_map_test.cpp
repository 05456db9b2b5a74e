#include "kernels/self_organizing_map.hpp"

#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

#include <gtest/gtest.h>
#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include "kernels/random_stream.hpp"

namespace ggk::kernels {
namespace {

// n samples in d dimensions from `clusters` Gaussian blobs (sd 20) whose centres
// are uniform in [0, 1023]^d, like IR readings.
RowMatrixXd clustered_samples(std::int32_t n, std::int32_t d, std::int32_t clusters,
                              std::uint64_t seed) {
  RandomStream rng(seed, 0, 0);
  RowMatrixXd centres(clusters, d);
  for (Eigen::Index i = 0; i < centres.size(); ++i) centres.data()[i] = rng.uniform(0.0, 1023.0);
  RowMatrixXd samples(n, d);
  for (std::int32_t i = 0; i < n; ++i) {
    const auto c = static_cast<Eigen::Index>(rng.uniform_index(clusters));
    for (std::int32_t j = 0; j < d; ++j) samples(i, j) = centres(c, j) + 20.0 * rng.normal();
  }
  return samples;
}

// Points t * direction (t uniform in [0, 1]) plus a little noise across it.
RowMatrixXd line_samples(std::int32_t n, std::uint64_t seed) {
  RandomStream rng(seed, 0, 0);
  const Eigen::RowVector3d direction(300.0, 600.0, -200.0);
  RowMatrixXd samples(n, 3);
  for (std::int32_t i = 0; i < n; ++i) {
    samples.row(i) = rng.uniform() * direction;
    for (int j = 0; j < 3; ++j) samples(i, j) += rng.normal();
  }
  return samples;
}

// The definition, written naively: sum of squares in dimension order, strict <.
BestMatch brute_force_bmu(const RowMatrixXd& prototypes, const double* x) {
  double best = std::numeric_limits<double>::infinity();
  std::int32_t best_unit = 0;
  for (Eigen::Index u = 0; u < prototypes.rows(); ++u) {
    double sum = 0.0;
    for (Eigen::Index j = 0; j < prototypes.cols(); ++j) {
      const double diff = x[j] - prototypes(u, j);
      sum += diff * diff;
    }
    if (sum < best) {
      best = sum;
      best_unit = static_cast<std::int32_t>(u);
    }
  }
  return {best_unit, std::sqrt(best)};
}

void expect_invalid(const std::function<void()>& call, const std::string& fragment) {
  try {
    call();
    ADD_FAILURE() << "no exception; expected one mentioning '" << fragment << "'";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
}

bool bit_identical(const RowMatrixXd& a, const RowMatrixXd& b) {
  return a.rows() == b.rows() && a.cols() == b.cols() &&
         std::memcmp(a.data(), b.data(), sizeof(double) * static_cast<std::size_t>(a.size())) == 0;
}

TEST(SomGrid, PaperSizeForTwentyThousandSamples) {
  const SomGrid paper = som_grid_for(20000, 29.0 / 24.0);
  EXPECT_EQ(paper.rows, 24);
  EXPECT_EQ(paper.cols, 29);
  const SomGrid square = som_grid_for(20000);
  EXPECT_EQ(square.rows, 26);  // 5 sqrt(20000) = 707 units, near-square
  EXPECT_EQ(square.cols, 27);
  const SomGrid elongated = som_grid_for(20000, 2.0);
  EXPECT_EQ(elongated.rows, 19);  // round(sqrt(707 / 2)), round(707 / 19)
  EXPECT_EQ(elongated.cols, 37);
}

TEST(SomGrid, AspectRatioMeasuredFromPrincipalComponents) {
  RandomStream rng(3, 0, 0);
  RowMatrixXd samples(20000, 8);
  const double sd[8] = {29.0, 24.0, 5.0, 4.0, 3.0, 2.0, 1.0, 1.0};
  for (Eigen::Index i = 0; i < samples.rows(); ++i)
    for (int j = 0; j < 8; ++j) samples(i, j) = 500.0 + sd[j] * rng.normal();
  // Rotate so that the principal axes are not the coordinate axes.
  Eigen::MatrixXd random_matrix(8, 8);
  for (Eigen::Index i = 0; i < random_matrix.size(); ++i) random_matrix.data()[i] = rng.normal();
  const Eigen::MatrixXd rotation =
      Eigen::HouseholderQR<Eigen::MatrixXd>(random_matrix).householderQ();
  const RowMatrixXd rotated = samples * rotation.transpose();
  EXPECT_NEAR(som_aspect_ratio(rotated, 707), 29.0 / 24.0, 0.03);
  const SomGrid grid = som_grid_for(rotated);
  EXPECT_EQ(grid.rows, 24);
  EXPECT_EQ(grid.cols, 29);
  // Nearly 1-D data falls back to near-square (SOM Toolbox rule).
  EXPECT_EQ(som_aspect_ratio(line_samples(2000, 4), 224), 1.0);
}

TEST(SomGrid, NeverMoreUnitsThanSamples) {
  for (std::int64_t n = 1; n <= 400; ++n) {
    for (double ratio : {1.0, 1.5, 4.0}) {
      const SomGrid g = som_grid_for(n, ratio);
      EXPECT_GE(g.rows, 1);
      EXPECT_LE(g.rows, g.cols);
      EXPECT_LE(g.units(), n) << n;
      // About min(5 sqrt(n), n) units, up to the rounding of the sides.
      const double target =
          std::min(5.0 * std::sqrt(static_cast<double>(n)), static_cast<double>(n));
      EXPECT_LE(std::abs(g.units() - target), std::max(0.1 * target, static_cast<double>(g.rows)))
          << n << " " << ratio;
    }
  }
}

TEST(SelfOrganizingMap, BestMatchEqualsBruteForceOnRandomData) {
  RandomStream rng(11, 0, 0);
  RowMatrixXd prototypes(13 * 7, 5);
  for (Eigen::Index i = 0; i < prototypes.size(); ++i) prototypes.data()[i] = rng.uniform(-1, 1);
  const SelfOrganizingMap map(13, 7, prototypes);
  RowMatrixXd queries(500, 5);
  for (Eigen::Index i = 0; i < queries.size(); ++i) queries.data()[i] = rng.uniform(-1.5, 1.5);
  const BestMatches batch = map.best_matching_units(queries);
  ASSERT_EQ(batch.units.size(), 500u);
  for (Eigen::Index i = 0; i < queries.rows(); ++i) {
    const BestMatch expected = brute_force_bmu(prototypes, queries.row(i).data());
    const auto k = static_cast<std::size_t>(i);
    EXPECT_EQ(batch.units[k], expected.unit) << i;
    EXPECT_EQ(batch.distances[k], expected.distance) << i;  // same sums, same order
    const BestMatch single =
        map.best_matching_unit(std::span<const double>(queries.row(i).data(), 5));
    EXPECT_EQ(single.unit, expected.unit);
    EXPECT_EQ(single.distance, expected.distance);
  }
}

// The batch search screens units with |m|^2 - 2 x.m through the BLAS; near ties
// below that expansion's rounding (prototypes a few ulps apart, far from the
// origin) must still go to the unit the exact loop picks. 700 queries span three
// query blocks.
TEST(SelfOrganizingMap, BatchSearchSettlesNearTiesExactly) {
  RandomStream rng(23, 0, 0);
  for (const double offset : {0.0, 1000.0, 1e6}) {
    RowMatrixXd prototypes(6 * 10, 8);
    for (Eigen::Index u = 0; u < prototypes.rows(); ++u) {
      for (Eigen::Index j = 0; j < 8; ++j) {
        // Pairs of units 1e-12 (relative) apart around a few base points.
        const double base = offset + static_cast<double>((u / 2) % 5 * (j + 1));
        prototypes(u, j) = base * (1.0 + (u % 2 == 0 ? 0.0 : 1e-12 * rng.uniform(-1, 1)));
      }
    }
    const SelfOrganizingMap map(6, 10, prototypes);
    RowMatrixXd queries(700, 8);
    for (Eigen::Index i = 0; i < queries.rows(); ++i) {
      const Eigen::Index u = static_cast<Eigen::Index>(rng.uniform_index(60));
      for (Eigen::Index j = 0; j < 8; ++j) {
        queries(i, j) = prototypes(u, j) + (i % 3 == 0 ? 0.0 : 1e-9 * offset * rng.normal());
      }
    }
    const BestMatches batch = map.best_matching_units(queries);
    for (Eigen::Index i = 0; i < queries.rows(); ++i) {
      const BestMatch expected = brute_force_bmu(prototypes, queries.row(i).data());
      const auto k = static_cast<std::size_t>(i);
      ASSERT_EQ(batch.units[k], expected.unit) << "offset " << offset << " query " << i;
      ASSERT_EQ(batch.distances[k], expected.distance) << "offset " << offset << " query " << i;
    }
  }
}

TEST(SelfOrganizingMap, TiesGoToTheLowestUnit) {
  // Integer coordinates in {0, 1, 2}: all sums are exact, so equal distances are
  // exact ties; 40 units over 27 points guarantees duplicated prototypes too.
  RandomStream rng(5, 0, 0);
  RowMatrixXd prototypes(5 * 8, 3);
  for (Eigen::Index i = 0; i < prototypes.size(); ++i)
    prototypes.data()[i] = static_cast<double>(rng.uniform_index(3));
  const SelfOrganizingMap map(5, 8, prototypes);
  RowMatrixXd queries(300, 3);
  for (Eigen::Index i = 0; i < queries.size(); ++i)
    queries.data()[i] = 0.5 * static_cast<double>(rng.uniform_index(5));
  const BestMatches batch = map.best_matching_units(queries);
  std::int32_t tied = 0;
  for (Eigen::Index i = 0; i < queries.rows(); ++i) {
    const BestMatch expected = brute_force_bmu(prototypes, queries.row(i).data());
    EXPECT_EQ(batch.units[static_cast<std::size_t>(i)], expected.unit) << i;
    std::int32_t at_best = 0;
    for (Eigen::Index u = 0; u < prototypes.rows(); ++u)
      at_best += (prototypes.row(u) - queries.row(i)).norm() == expected.distance;
    tied += at_best > 1;
  }
  EXPECT_GT(tied, 100);  // the test really exercises ties
  // A query equidistant from the last unit and one in the first tile.
  RowMatrixXd two = RowMatrixXd::Constant(2 * 9, 1, 100.0);
  two(17, 0) = 1.0;
  two(3, 0) = -1.0;
  const SelfOrganizingMap pair(2, 9, two);
  const std::vector<double> zero = {0.0};
  EXPECT_EQ(pair.best_matching_unit(zero).unit, 3);
  EXPECT_EQ(pair.best_matching_unit(zero).distance, 1.0);
}

TEST(SelfOrganizingMap, QuantizationErrorFallsOverEpochs) {
  const RowMatrixXd samples = clustered_samples(3000, 8, 5, 21);
  SomOptions options;
  options.rows = 8;
  options.cols = 10;
  options.epochs = 25;
  for (auto init : {SomInitialization::principal_components, SomInitialization::random_samples}) {
    options.initialization = init;
    RandomStream rng(21, 0, 1);
    const SelfOrganizingMap map = train_self_organizing_map(samples, options, &rng);
    const std::vector<double>& qe = map.quantization_errors();
    ASSERT_EQ(qe.size(), 25u);
    for (std::size_t t = 1; t < qe.size(); ++t) {
      EXPECT_LE(qe[t], qe[t - 1] * (1.0 + 1e-3)) << "epoch " << t;
    }
    EXPECT_LT(qe.back(), 0.3 * qe.front());
    // Each cluster has spread sd 20 per axis (about 20 sqrt(8) = 57 from its centre).
    EXPECT_LT(qe.back(), 57.0);
    // The recorded error is the one of the returned prototypes.
    const BestMatches matches = map.best_matching_units(samples);
    double mean = 0.0;
    for (double d : matches.distances) mean += d;
    EXPECT_DOUBLE_EQ(qe.back(), mean / 3000.0);
  }
}

TEST(SelfOrganizingMap, RadiusSchedules) {
  const RowMatrixXd samples = clustered_samples(200, 2, 3, 2);
  SomOptions options;
  options.rows = 4;
  options.cols = 10;
  options.epochs = 5;
  const SelfOrganizingMap exponential = train_self_organizing_map(samples, options);
  const std::vector<double>& r = exponential.radii();
  ASSERT_EQ(r.size(), 5u);
  EXPECT_DOUBLE_EQ(r.front(), 5.0);  // max(rows, cols) / 2
  EXPECT_DOUBLE_EQ(r.back(), 1.0);
  for (std::size_t t = 1; t < r.size(); ++t)
    EXPECT_NEAR(r[t] / r[t - 1], std::pow(0.2, 0.25), 1e-12);
  options.radius_schedule = SomRadiusSchedule::linear;
  options.initial_radius = 3.0;
  const std::vector<double> linear = train_self_organizing_map(samples, options).radii();
  for (std::size_t t = 0; t < linear.size(); ++t)
    EXPECT_NEAR(linear[t], 3.0 - 0.5 * static_cast<double>(t), 1e-12);
  options.epochs = 1;
  EXPECT_EQ(train_self_organizing_map(samples, options).radii(), std::vector<double>{1.0});
}

TEST(SelfOrganizingMap, UnitWithoutNeighbourhoodMassKeepsItsPrototype) {
  // Two tight groups at 0 and 10; the linear initialisation puts the middle unit
  // at the mean, 5, where no sample has its BMU. With radius 0.01 the neighbour
  // weights exp(-1 / 2e-4) underflow to 0, so its mass is exactly 0.
  RowMatrixXd samples(20, 1);
  for (int i = 0; i < 20; ++i) samples(i, 0) = i < 10 ? 0.0 : 10.0;
  SomOptions options;
  options.rows = 1;
  options.cols = 3;
  options.epochs = 3;
  options.initial_radius = 0.01;
  options.final_radius = 0.01;
  const SelfOrganizingMap map = train_self_organizing_map(samples, options);
  EXPECT_EQ(map.prototypes()(0, 0), 0.0);
  EXPECT_EQ(map.prototypes()(1, 0), 5.0);
  EXPECT_EQ(map.prototypes()(2, 0), 10.0);
  EXPECT_EQ(map.quantization_errors().back(), 0.0);
}

TEST(SelfOrganizingMap, DeterministicForSeedAndThreadCount) {
  const RowMatrixXd samples = clustered_samples(4000, 8, 6, 7);
  SomOptions options;
  options.rows = 12;
  options.cols = 15;
  options.epochs = 10;
  options.initialization = SomInitialization::random_samples;
  auto train = [&](std::uint64_t seed) {
    RandomStream rng(seed, 3, 9);
    return train_self_organizing_map(samples, options, &rng);
  };
  const SelfOrganizingMap first = train(17);
  EXPECT_TRUE(bit_identical(first.prototypes(), train(17).prototypes()));
  EXPECT_FALSE(bit_identical(first.prototypes(), train(18).prototypes()));

  // Lift oneTBB's default worker limit (cores - 1) so the arenas really get their threads.
  tbb::global_control allow(tbb::global_control::max_allowed_parallelism, 4);
  for (auto init : {SomInitialization::principal_components, SomInitialization::random_samples}) {
    options.initialization = init;
    auto run_with = [&](int threads) {
      tbb::task_arena arena(threads);
      RowMatrixXd prototypes;
      std::vector<double> qe;
      BestMatches matches;
      arena.execute([&] {
        RandomStream rng(17, 3, 9);
        const SelfOrganizingMap map = train_self_organizing_map(samples, options, &rng);
        prototypes = map.prototypes();
        qe = map.quantization_errors();
        matches = map.best_matching_units(samples);
      });
      return std::tuple{prototypes, qe, matches};
    };
    const auto [p1, qe1, m1] = run_with(1);
    const auto [p4, qe4, m4] = run_with(4);
    EXPECT_TRUE(bit_identical(p1, p4));
    EXPECT_EQ(qe1, qe4);  // exact comparison of doubles
    EXPECT_EQ(m1.units, m4.units);
    EXPECT_EQ(m1.distances, m4.distances);
  }
}

// Positions of the prototypes along the line's direction.
std::vector<double> along_line(const RowMatrixXd& prototypes) {
  const Eigen::RowVector3d direction = Eigen::RowVector3d(300.0, 600.0, -200.0).normalized();
  std::vector<double> t;
  for (Eigen::Index u = 0; u < prototypes.rows(); ++u)
    t.push_back(prototypes.row(u).dot(direction));
  return t;
}

bool strictly_monotone(const std::vector<double>& t) {
  bool increasing = true;
  bool decreasing = true;
  for (std::size_t i = 1; i < t.size(); ++i) {
    increasing = increasing && t[i] > t[i - 1];
    decreasing = decreasing && t[i] < t[i - 1];
  }
  return increasing || decreasing;
}

TEST(SelfOrganizingMap, LineDataGivesAnOrderedMap) {
  const RowMatrixXd samples = line_samples(2000, 8);
  SomOptions options;
  options.rows = 1;
  options.cols = 20;
  options.epochs = 30;
  // From random prototypes: the ordering must emerge from the shrinking neighbourhood.
  options.initialization = SomInitialization::random_samples;
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    RandomStream rng(seed, 0, 0);
    const SelfOrganizingMap map = train_self_organizing_map(samples, options, &rng);
    const std::vector<double> t = along_line(map.prototypes());
    EXPECT_TRUE(strictly_monotone(t)) << "seed " << seed;
    // Evenly spread over the line's length (700): neighbours about 700 / 20 apart.
    for (std::size_t i = 1; i < t.size(); ++i) EXPECT_LT(std::abs(t[i] - t[i - 1]), 70.0);
  }
  // A 2-D grid from the linear initialisation: every grid row is ordered along the
  // line, and grid neighbours (across rows too) hold nearby prototypes.
  options.rows = 3;
  options.cols = 16;
  options.initialization = SomInitialization::principal_components;
  const SelfOrganizingMap map = train_self_organizing_map(samples, options);
  for (std::int32_t r = 0; r < 3; ++r) {
    const RowMatrixXd row = map.prototypes().middleRows(r * 16, 16);
    EXPECT_TRUE(strictly_monotone(along_line(row))) << "row " << r;
  }
  for (std::int32_t u = 0; u < map.num_units(); ++u) {
    if (map.unit_col(u) + 1 < map.cols()) {
      EXPECT_LT((map.prototypes().row(u) - map.prototypes().row(u + 1)).norm(), 100.0);
    }
    if (map.unit_row(u) + 1 < map.rows()) {
      EXPECT_LT((map.prototypes().row(u) - map.prototypes().row(u + map.cols())).norm(), 100.0);
    }
  }
}

TEST(SelfOrganizingMap, GridCoordinates) {
  const SelfOrganizingMap map(2, 3, RowMatrixXd::Zero(6, 1));
  const RowMatrixXd g = map.grid_coordinates();
  ASSERT_EQ(g.rows(), 6);
  EXPECT_EQ(g(4, 0), 1.0);
  EXPECT_EQ(g(4, 1), 1.0);
  EXPECT_EQ(map.unit_at(1, 2), 5);
  EXPECT_EQ(map.unit_row(5), 1);
  EXPECT_EQ(map.unit_col(5), 2);
}

TEST(SelfOrganizingMap, RejectsBadOptionsAndShapes) {
  const RowMatrixXd samples = clustered_samples(50, 3, 2, 1);
  auto train_with = [&](const std::function<void(SomOptions&)>& change) {
    return [&samples, change] {
      SomOptions options;
      options.rows = 4;
      options.cols = 5;
      change(options);
      train_self_organizing_map(samples, options);
    };
  };
  expect_invalid(train_with([](SomOptions& o) { o.rows = 0; }), "at least one row");
  expect_invalid(train_with([](SomOptions& o) { o.cols = -2; }), "at least one row");
  expect_invalid(train_with([](SomOptions& o) { o.cols = 13; }),
                 "52 units (4 x 13) but only 50 samples");
  expect_invalid(train_with([](SomOptions& o) { o.epochs = 0; }), "epochs must be >= 1");
  expect_invalid(train_with([](SomOptions& o) { o.final_radius = 0.0; }), "radii");
  expect_invalid(train_with([](SomOptions& o) { o.initial_radius = 0.5; }), "radii");
  expect_invalid(
      train_with([](SomOptions& o) { o.initialization = SomInitialization::random_samples; }),
      "needs a RandomStream");
  RowMatrixXd with_nan = samples;
  with_nan(3, 1) = std::numeric_limits<double>::quiet_NaN();
  SomOptions small;
  small.rows = 2;
  small.cols = 2;
  expect_invalid([&] { train_self_organizing_map(with_nan, small); }, "NaN");
  expect_invalid([&] { train_self_organizing_map(RowMatrixXd(0, 3), SomOptions{}); },
                 "at least one sample");

  const SelfOrganizingMap map(2, 2, RowMatrixXd::Zero(4, 3));
  const std::vector<double> two = {1.0, 2.0};
  expect_invalid([&] { map.best_matching_unit(two); },
                 "query has 2 entries, the map's dimension is 3");
  expect_invalid([&] { map.best_matching_units(RowMatrixXd::Zero(5, 4)); },
                 "queries have dimension 4");
  const std::vector<double> inf = {1.0, std::numeric_limits<double>::infinity(), 0.0};
  expect_invalid([&] { map.best_matching_unit(inf); }, "NaN or infinity");
  expect_invalid([] { SelfOrganizingMap(2, 3, RowMatrixXd::Zero(5, 2)); }, "prototypes are 5 x 2");
  expect_invalid([] { SelfOrganizingMap(0, 3, RowMatrixXd::Zero(0, 2)); }, "at least one row");
  expect_invalid([] { som_grid_for(0); }, "at least one sample");
  expect_invalid([] { som_grid_for(100, 0.5); }, "aspect ratio");
}

}  // namespace
}  // namespace ggk::kernels
