#pragma once
// The continuous protocol's moves (continuous_protocol.hpp): the random walks
// that make a run's samples, the kernel values of an observation off the sample
// set, and the greedy episodes that test a fit.
//
// Thread-safety: reentrant; ObservationKernels is read-only once built and may
// be shared by the threads of one fit.

#include <cstdint>
#include <span>
#include <vector>

#include "engine/job/sweep.hpp"
#include "engine/tasks/continuous_protocol.hpp"
#include "engine/tasks/run_record.hpp"
#include "kernels/eigen_types.hpp"
#include "kernels/random_stream.hpp"
#include "kernels/sample_batch.hpp"
#include "kernels/self_organizing_map.hpp"

namespace ggk::engine {

// The random walks. States are the observations in series order: a series of T
// steps holds T + 1 consecutive states, its sample t going from state t to t + 1
// of the series (all series run the full protocol.steps_per_series unless one
// ends: observation k (steps + 1) + t of series k when none does).
struct Walks {
  kernels::RowMatrixXd observations;  // states x d, unscaled
  kernels::SampleBatch batch;
  std::vector<double> stop_flags;  // per sample, 1 if the step reported stop
};

// protocol.series walks of up to protocol.steps_per_series uniformly random
// actions (random.uniform_index), each from the environment's walk start; a
// series ends early on a terminal or truncated step. An EnvironmentError is
// rethrown naming the series and step.
Walks random_walks(const ContinuousEnvironment& env, const ContinuousProtocol& protocol,
                   kernels::RandomStream& random);

// The observations divided by the protocol's scale, per dimension (an empty
// scale: unchanged).
kernels::RowMatrixXd scaled_observations(const kernels::RowMatrixXd& observations,
                                         std::span<const double> scale);

// K(s, c_j) of a fit for one scaled observation, with the same arithmetic as the
// batch kernel functions (so a sample's features equal its row of the table).
// GGK in its continuous form ED(s, n(s)) + SP(n(s), c_j), n(s) the nearest
// occupied unit; OGK against the centre units' prototypes; PVF the first
// point.kernels proto-value functions at n(s) (engine/tasks/pvf_basis.hpp),
// untruncated. Every argument must outlive it.
class ObservationKernels {
 public:
  // occupied: per unit, whether it is a graph node; center_distances: SP from
  // the first centres (at least centers.size() rows) to every unit;
  // unit_eigenvectors (basis "pvf" only): units x P, P >= point.kernels.
  ObservationKernels(const kernels::SelfOrganizingMap& som, std::span<const std::uint8_t> occupied,
                     const kernels::RowMatrixXd& center_distances, const SweepPoint& point,
                     std::span<const std::int32_t> centers, double truncation,
                     const kernels::RowMatrixXd* unit_eigenvectors = nullptr);

  Eigen::VectorXd operator()(std::span<const double> scaled_observation) const;

 private:
  kernels::BestMatch nearest_graph_node(std::span<const double> observation) const;

  const kernels::SelfOrganizingMap& som_;
  std::span<const std::uint8_t> occupied_;
  const kernels::RowMatrixXd& center_distances_;
  const SweepPoint& point_;
  std::span<const std::int32_t> centers_;
  double truncation_;
  const kernels::RowMatrixXd* unit_eigenvectors_;
};

// Greedy action for kernel values k under the copy scheme: argmax_a w_a . k, ties
// to the lowest action (as kernels::greedy_policy).
std::int32_t greedy_action(const Eigen::VectorXd& weights, const Eigen::VectorXd& k,
                           std::int32_t num_actions);

// The protocol's test of greedy weights: protocol.test_episodes episodes from
// the environment's test start, each ended by a terminal, truncated or stop step
// or after protocol.test_max_steps, all drawn from `random` (pass a fresh copy of
// the run's evaluation stream, so every fit meets the same test noise and the
// test of the last iterate is the fit's own). An observation is featurised with
// the copy scheme (no transition model exists for a state off the sample set).
// An EnvironmentError is rethrown naming the episode and step.
struct EpisodeTest {
  double mean_return = 0.0;
  double ended_fraction = 0.0;  // episodes ended by a terminal or stop step
  double mean_steps = 0.0;
  std::vector<double> returns;
  std::vector<NamedArray> trajectories;  // evaluation/trajectory_<episode>, when asked
};

EpisodeTest test_episodes(const ContinuousEnvironment& env, const ContinuousProtocol& protocol,
                          kernels::RandomStream random, const ObservationKernels& kernels_of,
                          const Eigen::VectorXd& weights, bool keep_trajectories);

}  // namespace ggk::engine
