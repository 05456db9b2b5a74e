// The continuous protocol's moves (engine/tasks/continuous_episodes.hpp): the
// walks' state numbering (with series that end early), the scale, greedy ties to
// the lowest action, the episodes' bounds, ends and determinism for one stream,
// and an observation's PVF values from its nearest occupied unit.

#include "engine/tasks/continuous_episodes.hpp"

#include <cstdint>
#include <vector>

#include <gtest/gtest.h>

#include "engine/tasks/seeds.hpp"
#include "support/line_walker.hpp"

namespace ggk::engine {
namespace {

using test_support::line_walker_environment;
using test_support::line_walker_protocol;

TEST(ContinuousWalks, ObservationsInSeriesOrderOneSamplePerStep) {
  const ContinuousEnvironment env = line_walker_environment();
  ContinuousProtocol protocol = line_walker_protocol();
  kernels::RandomStream random = stream_for(1, 0, Purpose::samples);
  const Walks walks = random_walks(env, protocol, random);
  // Every series is its own run of consecutive states; a series ends after
  // steps_per_series steps or at its first terminal sample.
  ASSERT_EQ(walks.stop_flags.size(), walks.batch.size());
  std::int32_t series = 0, length = 0, terminals = 0;
  for (std::size_t i = 0; i < walks.batch.size(); ++i) {
    EXPECT_EQ(walks.batch.next_states[i], walks.batch.states[i] + 1);
    const bool starts = i == 0 || walks.batch.states[i] != walks.batch.next_states[i - 1];
    if (starts) {
      if (i > 0) {
        EXPECT_EQ(walks.batch.states[i], walks.batch.next_states[i - 1] + 1);
      }
      ++series;
      length = 0;
    }
    ++length;
    EXPECT_LE(length, protocol.steps_per_series);
    const bool last =
        i + 1 == walks.batch.size() || walks.batch.states[i + 1] != walks.batch.next_states[i];
    if (walks.batch.terminals[i]) {
      ++terminals;
      EXPECT_TRUE(last) << "a terminal sample ends its series";
      EXPECT_GE(walks.observations(walks.batch.next_states[i], 0), 10.0);
    } else if (last) {
      EXPECT_EQ(length, protocol.steps_per_series);
    }
    EXPECT_EQ(walks.stop_flags[i] == 1.0,
              walks.observations(walks.batch.next_states[i], 0) == -3.0);
  }
  EXPECT_EQ(series, protocol.series);
  EXPECT_GT(terminals, 0) << "the test walker must reach its goal in some series";
  EXPECT_EQ(walks.observations.rows(),
            static_cast<Eigen::Index>(walks.batch.size()) + protocol.series);
  for (Eigen::Index i = 0; i < walks.observations.rows(); ++i) {
    EXPECT_EQ(walks.observations(i, 1), 2.0 * walks.observations(i, 0));
  }

  // Without ends, observation k (steps + 1) + t of series k (the Khepera's layout).
  protocol.steps_per_series = 2;
  kernels::RandomStream again = stream_for(2, 0, Purpose::samples);
  const Walks short_walks = random_walks(env, protocol, again);
  for (std::size_t i = 0; i < short_walks.batch.size(); ++i) {
    if (short_walks.batch.terminals[i]) continue;
    EXPECT_EQ(short_walks.batch.states[i],
              static_cast<std::int32_t>(i / 2) * 3 + static_cast<std::int32_t>(i % 2));
  }
}

TEST(ContinuousWalks, ScaledObservationsDivideEachDimension) {
  kernels::RowMatrixXd x(2, 2);
  x << 3.0, 7.0, -1.0, 0.5;
  const std::vector<double> scale = {3.0, 0.25};
  const kernels::RowMatrixXd scaled = scaled_observations(x, scale);
  EXPECT_EQ(scaled(0, 0), 1.0);
  EXPECT_EQ(scaled(0, 1), 28.0);
  EXPECT_EQ(scaled(1, 0), -1.0 / 3.0);
  EXPECT_EQ(scaled(1, 1), 2.0);
  EXPECT_TRUE(scaled_observations(x, {}) == x);
}

TEST(ContinuousEpisodes, GreedyTiesGoToTheLowestAction) {
  const Eigen::VectorXd k = Eigen::VectorXd::Ones(2);
  Eigen::VectorXd weights(8);
  weights << 0.0, 0.0, 1.0, 1.0, 1.0, 1.0, 0.5, 0.5;
  EXPECT_EQ(greedy_action(weights, k, 4), 1);
}

struct TinyMap {
  Walks walks;
  kernels::SelfOrganizingMap som;
};

TinyMap tiny_map(const ContinuousEnvironment& env, const ContinuousProtocol& protocol) {
  kernels::RandomStream random = stream_for(1, 0, Purpose::samples);
  Walks walks = random_walks(env, protocol, random);
  kernels::SomOptions options;
  options.rows = 2;
  options.cols = 2;
  kernels::RandomStream som_stream = stream_for(1, 0, Purpose::model);
  kernels::SelfOrganizingMap som = kernels::train_self_organizing_map(
      scaled_observations(walks.observations, protocol.scale), options, &som_stream);
  return {std::move(walks), std::move(som)};
}

TEST(ContinuousEpisodes, BoundedEndedAndTheSameForTheSameStream) {
  const ContinuousEnvironment env = line_walker_environment();
  const ContinuousProtocol protocol = line_walker_protocol();
  const TinyMap map = tiny_map(env, protocol);
  const std::vector<std::uint8_t> occupied(4, 1);
  const kernels::RowMatrixXd distances = kernels::RowMatrixXd::Zero(2, 4);
  SweepPoint point;
  point.basis = KernelType::ogk;
  point.kernels = 2;
  point.sigma = 1.0;
  const std::vector<std::int32_t> centers = {0, 1};
  const ObservationKernels kernels_of(map.som, occupied, distances, point, centers, 0.0);
  const kernels::RandomStream evaluation = stream_for(1, 0, Purpose::evaluation);
  // Right always (w_right > w_left for positive kernels): the goal at 10 in 10 or
  // 11 steps, every episode.
  Eigen::VectorXd right(4);
  right << 0.0, 0.0, 1.0, 1.0;
  const EpisodeTest one = test_episodes(env, protocol, evaluation, kernels_of, right, true);
  const EpisodeTest two = test_episodes(env, protocol, evaluation, kernels_of, right, false);
  ASSERT_EQ(one.returns.size(), 3u);
  EXPECT_EQ(one.returns, two.returns);
  EXPECT_EQ(one.mean_steps, two.mean_steps);
  EXPECT_EQ(one.ended_fraction, 1.0);
  EXPECT_EQ(one.mean_return, 1.0);
  EXPECT_GE(one.mean_steps, 10.0);
  EXPECT_LE(one.mean_steps, 12.0);
  ASSERT_EQ(one.trajectories.size(), 3u);
  EXPECT_TRUE(two.trajectories.empty());
  for (const NamedArray& trajectory : one.trajectories) {
    ASSERT_EQ(trajectory.shape.size(), 2u);
    EXPECT_EQ(trajectory.shape[1], 1);
    EXPECT_EQ(trajectory.values.front(), 0.0);  // the test start
    EXPECT_GE(trajectory.values.back(), 10.0);  // the goal
  }
  // Left always: a bump (a stop) at -3 after 3 or 4 steps ends each episode.
  Eigen::VectorXd left(4);
  left << 1.0, 1.0, 0.0, 0.0;
  const EpisodeTest bumped = test_episodes(env, protocol, evaluation, kernels_of, left, false);
  EXPECT_EQ(bumped.ended_fraction, 1.0);
  EXPECT_EQ(bumped.mean_return, -1.0);
  EXPECT_LE(bumped.mean_steps, 4.0);
  // Neither: the cap (test_max_steps) ends every episode, none ended.
  ContinuousProtocol capped = protocol;
  capped.test_max_steps = 2;
  const EpisodeTest short_test = test_episodes(env, capped, evaluation, kernels_of, right, false);
  EXPECT_EQ(short_test.ended_fraction, 0.0);
  EXPECT_EQ(short_test.mean_steps, 2.0);
}

// Basis "pvf": an observation's values are its nearest occupied unit's entries
// of the unit eigenvectors (the first point.kernels), so an unoccupied best
// match falls back as the continuous GGK does.
TEST(ContinuousEpisodes, PvfObservationsTakeTheirNearestOccupiedUnitsValues) {
  const ContinuousEnvironment env = line_walker_environment();
  const ContinuousProtocol protocol = line_walker_protocol();
  const TinyMap map = tiny_map(env, protocol);
  const kernels::RowMatrixXd scaled = scaled_observations(map.walks.observations, protocol.scale);
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
    const ObservationKernels kernels_of(map.som, occupied, distances, point, no_centers, 0.5,
                                        &unit_values);
    for (Eigen::Index i = 0; i < scaled.rows(); ++i) {
      const auto row = scaled.row(i);
      const std::vector<double> observation(row.data(), row.data() + row.size());
      // The nearest occupied unit, by brute force (ties to the lowest unit).
      std::int32_t nearest = -1;
      double best = 0.0;
      for (std::int32_t u = 0; u < 4; ++u) {
        const double d = (row - map.som.prototypes().row(u)).norm();
        if (occupied[static_cast<std::size_t>(u)] && (nearest < 0 || d < best)) {
          nearest = u;
          best = d;
        }
      }
      const Eigen::VectorXd k = kernels_of(observation);
      ASSERT_EQ(k.size(), 2);
      EXPECT_EQ(k[0], unit_values(nearest, 0));
      EXPECT_EQ(k[1], unit_values(nearest, 1));  // untruncated: 0.5 does not apply
    }
  }
}

}  // namespace
}  // namespace ggk::engine
