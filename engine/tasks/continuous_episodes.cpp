#include "engine/tasks/continuous_episodes.hpp"

#include <limits>
#include <numeric>
#include <string>
#include <utility>

#include "kernels/gaussian_kernels.hpp"

namespace ggk::engine {

namespace {

std::span<double> row_span(kernels::RowMatrixXd& matrix, Eigen::Index row) {
  return {matrix.row(row).data(), static_cast<std::size_t>(matrix.cols())};
}

}  // namespace

Walks random_walks(const ContinuousEnvironment& env, const ContinuousProtocol& protocol,
                   kernels::RandomStream& random) {
  const std::int32_t d = env.observation_dimension;
  Walks walks;
  walks.observations.resize(
      static_cast<Eigen::Index>(protocol.series) * (protocol.steps_per_series + 1), d);
  const std::unique_ptr<ContinuousEpisode> episode = env.new_episode();
  Eigen::Index state = 0;  // the series' current observation
  for (std::int32_t series = 0; series < protocol.series; ++series) {
    const auto where = [&](std::int32_t t, const EnvironmentError& error) {
      return EnvironmentError("the walks' series " + std::to_string(series) +
                              (t < 0 ? ", its start" : ", step " + std::to_string(t)) + ": " +
                              error.what());
    };
    try {
      episode->start_walk(random, row_span(walks.observations, state));
    } catch (const EnvironmentError& error) {
      throw where(-1, error);
    }
    for (std::int32_t t = 0; t < protocol.steps_per_series; ++t) {
      const auto action = static_cast<std::int32_t>(random.uniform_index(env.num_actions));
      ContinuousStep step;
      try {
        step = episode->step(action, random, row_span(walks.observations, state + 1));
      } catch (const EnvironmentError& error) {
        throw where(t, error);
      }
      walks.batch.add(static_cast<std::int32_t>(state), action, step.reward,
                      static_cast<std::int32_t>(state + 1), step.terminal);
      walks.stop_flags.push_back(step.stop ? 1.0 : 0.0);
      ++state;
      if (step.terminal || step.truncated) break;
    }
    ++state;  // past the series' last observation
  }
  if (state < walks.observations.rows()) walks.observations.conservativeResize(state, d);
  return walks;
}

kernels::RowMatrixXd scaled_observations(const kernels::RowMatrixXd& observations,
                                         std::span<const double> scale) {
  kernels::RowMatrixXd scaled = observations;
  for (std::size_t j = 0; j < scale.size(); ++j) {
    scaled.col(static_cast<Eigen::Index>(j)) /= scale[j];
  }
  return scaled;
}

ObservationKernels::ObservationKernels(const kernels::SelfOrganizingMap& som,
                                       std::span<const std::uint8_t> occupied,
                                       const kernels::RowMatrixXd& center_distances,
                                       const SweepPoint& point,
                                       std::span<const std::int32_t> centers, double truncation,
                                       const kernels::RowMatrixXd* unit_eigenvectors)
    : som_(som),
      occupied_(occupied),
      center_distances_(center_distances),
      point_(point),
      centers_(centers),
      truncation_(truncation),
      unit_eigenvectors_(unit_eigenvectors) {}

Eigen::VectorXd ObservationKernels::operator()(std::span<const double> observation) const {
  if (point_.basis == KernelType::pvf) {
    return unit_eigenvectors_->row(nearest_graph_node(observation).unit)
        .head(point_.kernels)
        .transpose();
  }
  const auto p = static_cast<Eigen::Index>(centers_.size());
  Eigen::VectorXd k(p);
  if (point_.basis == KernelType::ggk) {
    const kernels::BestMatch bmu = nearest_graph_node(observation);
    for (Eigen::Index j = 0; j < p; ++j) {
      k(j) = kernels::gaussian(bmu.distance + center_distances_(j, bmu.unit), point_.sigma);
    }
  } else {
    const Eigen::Map<const Eigen::RowVectorXd> x(observation.data(),
                                                 static_cast<Eigen::Index>(observation.size()));
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
// to it is infinite), so an observation whose best match is such a unit falls
// back to the nearest occupied unit instead of getting all-zero features. For
// the samples' own observations this is their best match.
kernels::BestMatch ObservationKernels::nearest_graph_node(
    std::span<const double> observation) const {
  const kernels::BestMatch bmu = som_.best_matching_unit(observation);
  if (occupied_[static_cast<std::size_t>(bmu.unit)]) return bmu;
  const Eigen::Map<const Eigen::RowVectorXd> x(observation.data(),
                                               static_cast<Eigen::Index>(observation.size()));
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

EpisodeTest test_episodes(const ContinuousEnvironment& env, const ContinuousProtocol& protocol,
                          kernels::RandomStream random, const ObservationKernels& kernels_of,
                          const Eigen::VectorXd& weights, bool keep_trajectories) {
  const auto d = static_cast<std::size_t>(env.observation_dimension);
  const auto trace = static_cast<std::int64_t>(env.trace_dimension);
  const std::unique_ptr<ContinuousEpisode> episode = env.new_episode();
  std::vector<double> observation(d), scaled(d);
  const auto scale_observation = [&] {
    for (std::size_t j = 0; j < d; ++j) {
      scaled[j] = protocol.scale.empty() ? observation[j] : observation[j] / protocol.scale[j];
    }
  };
  EpisodeTest test;
  double steps_taken = 0.0;
  std::int32_t ended_episodes = 0;
  for (std::int32_t e = 0; e < protocol.test_episodes; ++e) {
    const auto where = [&](std::int32_t t, const EnvironmentError& error) {
      return EnvironmentError("test episode " + std::to_string(e) +
                              (t < 0 ? ", its start" : ", step " + std::to_string(t)) + ": " +
                              error.what());
    };
    try {
      episode->start_test(random, observation);
    } catch (const EnvironmentError& error) {
      throw where(-1, error);
    }
    NamedArray trajectory{"evaluation/trajectory_" + std::to_string(e), {0, trace}, {}};
    if (keep_trajectories) episode->trace(trajectory.values);
    double total = 0.0;
    std::int32_t steps = 0;
    for (; steps < protocol.test_max_steps; ++steps) {
      scale_observation();
      const std::int32_t action = greedy_action(weights, kernels_of(scaled), env.num_actions);
      ContinuousStep r;
      try {
        r = episode->step(action, random, observation);
      } catch (const EnvironmentError& error) {
        throw where(steps, error);
      }
      total += r.reward;
      if (keep_trajectories) episode->trace(trajectory.values);
      if (r.terminal || r.stop) ++ended_episodes;
      if (r.terminal || r.stop || r.truncated) {
        ++steps;
        break;
      }
    }
    if (keep_trajectories) {
      trajectory.shape[0] = static_cast<std::int64_t>(trajectory.values.size()) / trace;
      test.trajectories.push_back(std::move(trajectory));
    }
    test.returns.push_back(total);
    steps_taken += steps;
  }
  const auto episodes = static_cast<double>(protocol.test_episodes);
  test.mean_return = std::accumulate(test.returns.begin(), test.returns.end(), 0.0) / episodes;
  test.ended_fraction = ended_episodes / episodes;
  test.mean_steps = steps_taken / episodes;
  return test;
}

}  // namespace ggk::engine
