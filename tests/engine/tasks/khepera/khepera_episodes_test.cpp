// The Khepera task's moves (engine/tasks/khepera/khepera_episodes.hpp): the
// walks' state numbering, greedy ties to the lowest action, and the episodes'
// bounds and their determinism for one stream.

#include "engine/tasks/khepera/khepera_episodes.hpp"

#include <cstdint>
#include <vector>

#include <gtest/gtest.h>

#include "engine/tasks/seeds.hpp"

namespace ggk::engine {
namespace {

namespace khepera = sims::khepera;

khepera::KheperaConfig small_config() {
  khepera::KheperaConfig config;
  config.series = 3;
  config.steps_per_series = 4;
  config.test_episodes = 2;
  config.test_max_steps = 20;
  return config;
}

TEST(KheperaWalks, ReadingsInSeriesOrderOneSamplePerStep) {
  const khepera::Khepera robot(small_config());
  kernels::RandomStream random = stream_for(1, 0, Purpose::samples);
  const Walks walks = random_walks(robot, random);
  EXPECT_EQ(walks.readings.rows(), 3 * 5);
  EXPECT_EQ(walks.readings.cols(), khepera::kNumSensors);
  ASSERT_EQ(walks.batch.size(), 12u);
  ASSERT_EQ(walks.collisions.size(), 12u);
  for (std::size_t i = 0; i < walks.batch.size(); ++i) {
    const auto series = static_cast<std::int32_t>(i / 4), t = static_cast<std::int32_t>(i % 4);
    EXPECT_EQ(walks.batch.states[i], series * 5 + t);
    EXPECT_EQ(walks.batch.next_states[i], series * 5 + t + 1);
  }
}

TEST(KheperaEpisodes, GreedyTiesGoToTheLowestAction) {
  const Eigen::VectorXd k = Eigen::VectorXd::Ones(2);
  Eigen::VectorXd weights(8);
  weights << 0.0, 0.0, 1.0, 1.0, 1.0, 1.0, 0.5, 0.5;
  EXPECT_EQ(greedy_action(weights, k, 4), 1);
}

TEST(KheperaEpisodes, BoundedAndTheSameForTheSameStream) {
  const khepera::Khepera robot(small_config());
  kernels::RandomStream random = stream_for(1, 0, Purpose::samples);
  const Walks walks = random_walks(robot, random);
  kernels::SomOptions options;
  options.rows = 2;
  options.cols = 2;
  kernels::RandomStream som_stream = stream_for(1, 0, Purpose::model);
  const kernels::SelfOrganizingMap som =
      kernels::train_self_organizing_map(walks.readings, options, &som_stream);
  const std::vector<std::uint8_t> occupied(4, 1);
  const kernels::RowMatrixXd distances = kernels::RowMatrixXd::Zero(2, 4);
  SweepPoint point;
  point.basis = KernelType::ogk;
  point.kernels = 2;
  point.sigma = 1000.0;
  const std::vector<std::int32_t> centers = {0, 1};
  const ReadingKernels kernels_of(som, occupied, distances, point, centers, 0.0);
  const Eigen::VectorXd weights = Eigen::VectorXd::LinSpaced(8, -1.0, 1.0);
  const kernels::RandomStream evaluation = stream_for(1, 0, Purpose::evaluation);
  const EpisodeTest one = test_episodes(robot, evaluation, kernels_of, weights, true);
  const EpisodeTest two = test_episodes(robot, evaluation, kernels_of, weights, false);
  ASSERT_EQ(one.returns.size(), 2u);
  EXPECT_EQ(one.returns, two.returns);
  EXPECT_EQ(one.trajectories.size(), 2u);
  EXPECT_TRUE(two.trajectories.empty());
  EXPECT_GE(one.mean_steps, 1.0);
  EXPECT_LE(one.mean_steps, 20.0);
  EXPECT_GE(one.collision_fraction, 0.0);
  EXPECT_LE(one.collision_fraction, 1.0);
}

// Basis "pvf": a reading's values are its nearest occupied unit's entries of the
// unit eigenvectors (the first point.kernels), so an unoccupied best match falls
// back as the continuous GGK does.
TEST(KheperaEpisodes, PvfReadingsTakeTheirNearestOccupiedUnitsValues) {
  const khepera::Khepera robot(small_config());
  kernels::RandomStream random = stream_for(1, 0, Purpose::samples);
  const Walks walks = random_walks(robot, random);
  kernels::SomOptions options;
  options.rows = 2;
  options.cols = 2;
  kernels::RandomStream som_stream = stream_for(1, 0, Purpose::model);
  const kernels::SelfOrganizingMap som =
      kernels::train_self_organizing_map(walks.readings, options, &som_stream);
  kernels::RowMatrixXd unit_values(4, 3);
  unit_values << 0.1, -0.2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12;
  SweepPoint point;
  point.basis = KernelType::pvf;
  point.kernels = 2;
  const kernels::RowMatrixXd distances;
  const std::vector<std::int32_t> no_centers;
  for (std::int32_t hole = 0; hole < 4; ++hole) {
    std::vector<std::uint8_t> occupied(4, 1);
    occupied[static_cast<std::size_t>(hole)] = 0;
    const ReadingKernels kernels_of(som, occupied, distances, point, no_centers, 0.5, &unit_values);
    for (Eigen::Index i = 0; i < walks.readings.rows(); ++i) {
      const auto row = walks.readings.row(i);
      const std::vector<double> reading(row.data(), row.data() + row.size());
      // The nearest occupied unit, by brute force (ties to the lowest unit).
      std::int32_t nearest = -1;
      double best = 0.0;
      for (std::int32_t u = 0; u < 4; ++u) {
        const double d = (row - som.prototypes().row(u)).norm();
        if (occupied[static_cast<std::size_t>(u)] && (nearest < 0 || d < best)) {
          nearest = u;
          best = d;
        }
      }
      const Eigen::VectorXd k = kernels_of(reading);
      ASSERT_EQ(k.size(), 2);
      EXPECT_EQ(k[0], unit_values(nearest, 0));
      EXPECT_EQ(k[1], unit_values(nearest, 1));  // untruncated: 0.5 does not apply
    }
  }
}

}  // namespace
}  // namespace ggk::engine
