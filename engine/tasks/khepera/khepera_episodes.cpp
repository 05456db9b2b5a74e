#include "engine/tasks/khepera/khepera_episodes.hpp"

#include <limits>
#include <numeric>
#include <string>
#include <utility>

#include "kernels/gaussian_kernels.hpp"

namespace ggk::engine {

namespace khepera = sims::khepera;

Walks random_walks(const khepera::Khepera& robot, kernels::RandomStream& random) {
  const auto& c = robot.config();
  const std::int32_t per_series = c.steps_per_series + 1;
  Walks walks;
  walks.readings.resize(static_cast<Eigen::Index>(c.series) * per_series, khepera::kNumSensors);
  for (std::int32_t series = 0; series < c.series; ++series) {
    khepera::Pose pose = robot.sample_free_pose(random);
    const std::int32_t first = series * per_series;
    const khepera::Readings start = robot.sense(pose, random);
    for (std::int32_t d = 0; d < khepera::kNumSensors; ++d) walks.readings(first, d) = start[d];
    for (std::int32_t t = 0; t < c.steps_per_series; ++t) {
      const auto action = static_cast<std::int32_t>(random.uniform_index(robot.num_actions()));
      const khepera::StepResult r = robot.step(pose, action, random);
      for (std::int32_t d = 0; d < khepera::kNumSensors; ++d) {
        walks.readings(first + t + 1, d) = r.observation[d];
      }
      walks.batch.add(first + t, action, r.reward, first + t + 1, false);
      walks.collisions.push_back(r.collided ? 1.0 : 0.0);
      pose = r.next_pose;
    }
  }
  return walks;
}

ReadingKernels::ReadingKernels(const kernels::SelfOrganizingMap& som,
                               std::span<const std::uint8_t> occupied,
                               const kernels::RowMatrixXd& center_distances,
                               const SweepPoint& point, std::span<const std::int32_t> centers,
                               double truncation, const kernels::RowMatrixXd* unit_eigenvectors)
    : som_(som),
      occupied_(occupied),
      center_distances_(center_distances),
      point_(point),
      centers_(centers),
      truncation_(truncation),
      unit_eigenvectors_(unit_eigenvectors) {}

Eigen::VectorXd ReadingKernels::operator()(std::span<const double> reading) const {
  if (point_.basis == KernelType::pvf) {
    return unit_eigenvectors_->row(nearest_graph_node(reading).unit)
        .head(point_.kernels)
        .transpose();
  }
  const auto p = static_cast<Eigen::Index>(centers_.size());
  Eigen::VectorXd k(p);
  if (point_.basis == KernelType::ggk) {
    const kernels::BestMatch bmu = nearest_graph_node(reading);
    for (Eigen::Index j = 0; j < p; ++j) {
      k(j) = kernels::gaussian(bmu.distance + center_distances_(j, bmu.unit), point_.sigma);
    }
  } else {
    const Eigen::Map<const Eigen::RowVectorXd> x(reading.data(),
                                                 static_cast<Eigen::Index>(reading.size()));
    for (Eigen::Index j = 0; j < p; ++j) {
      k(j) = kernels::gaussian(
          (x - som_.prototypes().row(centers_[static_cast<std::size_t>(j)])).norm(), point_.sigma);
    }
  }
  for (Eigen::Index j = 0; j < p; ++j) {
    if (!(k(j) > 0.0 && k(j) >= truncation_)) k(j) = 0.0;
  }
  return k;
}

// n(s) of the continuous GGK: the nearest unit that is a node of the sample
// graph. A unit no sample maps to is isolated (every shortest path from a centre
// to it is infinite), so a reading whose best match is such a unit falls back to
// the nearest occupied unit instead of getting all-zero features. For the
// samples' own readings this is their best match.
kernels::BestMatch ReadingKernels::nearest_graph_node(std::span<const double> reading) const {
  const kernels::BestMatch bmu = som_.best_matching_unit(reading);
  if (occupied_[static_cast<std::size_t>(bmu.unit)]) return bmu;
  const Eigen::Map<const Eigen::RowVectorXd> x(reading.data(),
                                               static_cast<Eigen::Index>(reading.size()));
  kernels::BestMatch best{-1, std::numeric_limits<double>::infinity()};
  for (std::int32_t u = 0; u < som_.num_units(); ++u) {
    if (!occupied_[static_cast<std::size_t>(u)]) continue;
    const double d = (x - som_.prototypes().row(u)).norm();
    if (d < best.distance) best = {u, d};
  }
  return best;
}

std::int32_t greedy_action(const Eigen::VectorXd& weights, const Eigen::VectorXd& k,
                           std::int32_t num_actions) {
  const Eigen::Index p = k.size();
  std::int32_t best = 0;
  double best_q = -std::numeric_limits<double>::infinity();
  for (std::int32_t a = 0; a < num_actions; ++a) {
    const double q = weights.segment(a * p, p).dot(k);
    if (q > best_q) {
      best_q = q;
      best = a;
    }
  }
  return best;
}

EpisodeTest test_episodes(const khepera::Khepera& robot, kernels::RandomStream random,
                          const ReadingKernels& kernels_of, const Eigen::VectorXd& weights,
                          bool keep_trajectories) {
  const std::int32_t m = robot.num_actions();
  const auto& c = robot.config();
  EpisodeTest test;
  double steps_survived = 0.0;
  std::int32_t collided_episodes = 0;
  for (std::int32_t episode = 0; episode < c.test_episodes; ++episode) {
    khepera::Pose pose = robot.start_pose();
    khepera::Readings reading = robot.sense(pose, random);
    NamedArray trajectory{"evaluation/trajectory_" + std::to_string(episode), {0, 3}, {}};
    if (keep_trajectories) {
      trajectory.values.insert(trajectory.values.end(), {pose.x, pose.y, pose.heading});
    }
    double total = 0.0;
    std::int32_t steps = 0;
    for (; steps < c.test_max_steps; ++steps) {
      const std::int32_t action = greedy_action(weights, kernels_of(reading), m);
      const khepera::StepResult r = robot.step(pose, action, random);
      total += r.reward;
      pose = r.next_pose;
      reading = r.observation;
      if (keep_trajectories) {
        trajectory.values.insert(trajectory.values.end(), {pose.x, pose.y, pose.heading});
      }
      if (r.collided) {
        ++collided_episodes;
        ++steps;
        break;
      }
    }
    if (keep_trajectories) {
      trajectory.shape[0] = static_cast<std::int64_t>(trajectory.values.size() / 3);
      test.trajectories.push_back(std::move(trajectory));
    }
    test.returns.push_back(total);
    steps_survived += steps;
  }
  const auto episodes = static_cast<double>(c.test_episodes);
  test.mean_return = std::accumulate(test.returns.begin(), test.returns.end(), 0.0) / episodes;
  test.collision_fraction = collided_episodes / episodes;
  test.mean_steps = steps_survived / episodes;
  return test;
}

}  // namespace ggk::engine
