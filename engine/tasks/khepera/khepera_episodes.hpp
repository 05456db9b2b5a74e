#pragma once
// The Khepera task's moves in the simulator: the random walks that make a run's
// samples, the kernel values of a reading off the sample set, and the greedy
// episodes that test a fit (paper sec. 4.2).
//
// Thread-safety: reentrant; ReadingKernels is read-only once built and may be
// shared by the threads of one fit.

#include <cstdint>
#include <span>
#include <vector>

#include "engine/job/sweep.hpp"
#include "engine/tasks/run_record.hpp"
#include "kernels/eigen_types.hpp"
#include "kernels/random_stream.hpp"
#include "kernels/sample_batch.hpp"
#include "kernels/self_organizing_map.hpp"
#include "sims/khepera/khepera.hpp"

namespace ggk::engine {

// The random walks. States are the readings in series order: reading t of series
// k is state k * (steps + 1) + t; sample (k, t) goes from state (k, t) to (k, t + 1).
struct Walks {
  kernels::RowMatrixXd readings;  // states x 8
  kernels::SampleBatch batch;
  std::vector<double> collisions;  // per sample, 1 if the step was undone
};

// config().series walks of config().steps_per_series uniformly random actions,
// each from a random free pose.
Walks random_walks(const sims::khepera::Khepera& robot, kernels::RandomStream& random);

// K(s, c_j) of a fit for one reading, with the same arithmetic as the batch
// kernel functions (so a sample's features equal its row of the table). GGK in
// its continuous form ED(s, n(s)) + SP(n(s), c_j), n(s) the nearest occupied
// unit; OGK against the centre units' prototypes; PVF the first point.kernels
// proto-value functions at n(s) (engine/tasks/pvf_basis.hpp), untruncated.
// Every argument must outlive it.
class ReadingKernels {
 public:
  // occupied: per unit, whether it is a graph node; center_distances: SP from
  // the first centres (at least centers.size() rows) to every unit;
  // unit_eigenvectors (basis "pvf" only): units x P, P >= point.kernels.
  ReadingKernels(const kernels::SelfOrganizingMap& som, std::span<const std::uint8_t> occupied,
                 const kernels::RowMatrixXd& center_distances, const SweepPoint& point,
                 std::span<const std::int32_t> centers, double truncation,
                 const kernels::RowMatrixXd* unit_eigenvectors = nullptr);

  Eigen::VectorXd operator()(std::span<const double> reading) const;

 private:
  kernels::BestMatch nearest_graph_node(std::span<const double> reading) const;

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

// The protocol's test of greedy weights: config().test_episodes episodes from
// the start pose, each stopped by a collision or after test_max_steps, all drawn
// from `random` (pass a fresh copy of the fit's evaluation stream, so the test
// of the last iterate is the fit's own test). A reading is featurised with the
// copy scheme (no transition model exists for a reading off the sample set).
struct EpisodeTest {
  double mean_return = 0.0;
  double collision_fraction = 0.0;
  double mean_steps = 0.0;
  std::vector<double> returns;
  std::vector<NamedArray> trajectories;  // evaluation/trajectory_<episode>, when asked
};

EpisodeTest test_episodes(const sims::khepera::Khepera& robot, kernels::RandomStream random,
                          const ReadingKernels& kernels_of, const Eigen::VectorXd& weights,
                          bool keep_trajectories);

}  // namespace ggk::engine
