#include "engine/tasks/discrete_protocol.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>
#include <string>
#include <utility>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "engine/tasks/seeds.hpp"
#include "kernels/gaussian_kernels.hpp"
#include "kernels/graph_diagnostics.hpp"
#include "kernels/shortest_paths.hpp"
#include "kernels/state_action_basis.hpp"
#include "kernels/transition_model.hpp"

namespace ggk::engine {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Uniformly random actions in `series` series from uniformly random start
// states; see DiscreteProtocol::walk_through_goals for what follows a goal.
kernels::SampleBatch collect_samples(const DiscreteEnvironment& env,
                                     const DiscreteProtocol& protocol,
                                     kernels::RandomStream& random) {
  kernels::SampleBatch batch;
  const auto total = static_cast<std::size_t>(protocol.series) * protocol.steps_per_series;
  batch.states.reserve(total);
  auto random_start = [&] {
    return env.start_states[static_cast<std::size_t>(
        random.uniform_index(static_cast<std::int64_t>(env.start_states.size())))];
  };
  for (std::int32_t series = 0; series < protocol.series; ++series) {
    std::int32_t state = random_start();
    for (std::int32_t step = 0; step < protocol.steps_per_series; ++step) {
      const auto action = static_cast<std::int32_t>(random.uniform_index(env.num_actions));
      const Transition t = env.step(state, action, random);
      batch.add(state, action, t.reward, t.next_state, t.terminal);
      state = t.terminal && !protocol.walk_through_goals ? random_start() : t.next_state;
    }
  }
  return batch;
}

SampleRecord to_sample_record(const DiscreteEnvironment& env, const kernels::SampleBatch& batch) {
  SampleRecord record;
  const auto n = static_cast<Eigen::Index>(batch.size());
  const Eigen::Index d = env.state_vectors.cols();
  record.observations.resize(n, d);
  record.next_observations.resize(n, d);
  for (Eigen::Index i = 0; i < n; ++i) {
    record.observations.row(i) = env.state_vectors.row(batch.states[static_cast<std::size_t>(i)]);
    record.next_observations.row(i) =
        env.state_vectors.row(batch.next_states[static_cast<std::size_t>(i)]);
  }
  record.actions = batch.actions;
  record.rewards = batch.rewards;
  record.terminals = batch.terminals;
  return record;
}

// Goals that were visited, in id order, then the other visited states in a
// random order: the first p entries are the centres of a fit with p kernels.
std::vector<std::int32_t> center_order(const DiscreteEnvironment& env,
                                       const std::vector<std::uint8_t>& visited,
                                       kernels::RandomStream& random) {
  std::vector<std::int32_t> order, others;
  std::vector<std::uint8_t> is_goal(static_cast<std::size_t>(env.num_states), 0);
  for (std::int32_t g : env.goal_states) {
    is_goal[static_cast<std::size_t>(g)] = 1;
    if (visited[static_cast<std::size_t>(g)]) order.push_back(g);
  }
  for (std::int32_t s = 0; s < env.num_states; ++s) {
    if (visited[static_cast<std::size_t>(s)] && !is_goal[static_cast<std::size_t>(s)]) {
      others.push_back(s);
    }
  }
  kernels::shuffle(others, random);
  order.insert(order.end(), others.begin(), others.end());
  return order;
}

// Euclidean distance between the state vectors of states a and b. Every distance
// nearest_visited_states() compares or returns is this one expression, so that
// its results are those of a scan over all visited states, bit for bit.
double state_distance(const kernels::RowMatrixXd& vectors, std::int32_t a, std::int32_t b) {
  return (vectors.row(a) - vectors.row(b)).norm();
}

// A k-d tree over the visited states, for nearest-neighbour queries that give
// exactly what a scan in id order gives: the smallest computed distance, ties to
// the lowest id. A subtree is skipped only when the distance from the query to
// its splitting plane, which bounds every distance inside it from below, exceeds
// the best distance by more than any rounding of the computed distances (a
// relative 1e-9, against errors of a few ulps), so every state at the best
// distance is compared. O(n log n) to build, about O(log n) per query on grids.
class VisitedStateTree {
 public:
  VisitedStateTree(const kernels::RowMatrixXd& vectors, std::vector<std::int32_t> states)
      : vectors_(vectors), states_(std::move(states)) {
    if (!states_.empty()) build(0, static_cast<std::int32_t>(states_.size()));
  }

  // The visited state nearest to `state` and its distance; requires a non-empty tree.
  std::pair<std::int32_t, double> nearest(std::int32_t state) const {
    Best best{-1, std::numeric_limits<double>::infinity()};
    search(0, state, best);
    return {best.state, best.distance};
  }

 private:
  static constexpr std::int32_t kLeafSize = 8;
  // Rounding allowance of the pruning test (see the class comment).
  static constexpr double kPruneSlack = 1.0 - 1e-9;

  struct Node {
    std::int32_t begin = 0, end = 0;  // states_[begin, end)
    Eigen::Index axis = -1;           // -1 for a leaf
    double split = 0.0;               // left subtree: coordinate <= split; right: >= split
    std::int32_t left = -1, right = -1;
  };
  struct Best {
    std::int32_t state;
    double distance;
  };

  std::int32_t build(std::int32_t begin, std::int32_t end) {
    const auto id = static_cast<std::int32_t>(nodes_.size());
    nodes_.push_back({begin, end});
    if (end - begin <= kLeafSize) return id;
    // Split the widest coordinate at its median.
    Eigen::Index axis = 0;
    double widest = -1.0;
    for (Eigen::Index k = 0; k < vectors_.cols(); ++k) {
      double lo = std::numeric_limits<double>::infinity(), hi = -lo;
      for (std::int32_t i = begin; i < end; ++i) {
        const double x = vectors_(states_[static_cast<std::size_t>(i)], k);
        lo = std::min(lo, x);
        hi = std::max(hi, x);
      }
      if (hi - lo > widest) {
        widest = hi - lo;
        axis = k;
      }
    }
    if (!(widest > 0.0)) return id;  // all equal along every axis: one leaf
    const std::int32_t mid = begin + (end - begin) / 2;
    const auto first = states_.begin() + begin;
    std::nth_element(
        first, states_.begin() + mid, states_.begin() + end,
        [&](std::int32_t a, std::int32_t b) { return vectors_(a, axis) < vectors_(b, axis); });
    const double split = vectors_(states_[static_cast<std::size_t>(mid)], axis);
    const std::int32_t left = build(begin, mid);
    const std::int32_t right = build(mid, end);
    Node& node = nodes_[static_cast<std::size_t>(id)];
    node.axis = axis;
    node.split = split;
    node.left = left;
    node.right = right;
    return id;
  }

  void search(std::int32_t id, std::int32_t query, Best& best) const {
    const Node& node = nodes_[static_cast<std::size_t>(id)];
    if (node.axis < 0) {
      for (std::int32_t i = node.begin; i < node.end; ++i) {
        const std::int32_t v = states_[static_cast<std::size_t>(i)];
        const double d = state_distance(vectors_, query, v);
        if (d < best.distance || (d == best.distance && v < best.state)) best = {v, d};
      }
      return;
    }
    const double offset = vectors_(query, node.axis) - node.split;
    const std::int32_t near = offset <= 0.0 ? node.left : node.right;
    const std::int32_t far = offset <= 0.0 ? node.right : node.left;
    search(near, query, best);
    if (std::abs(offset) * kPruneSlack <= best.distance) search(far, query, best);
  }

  const kernels::RowMatrixXd& vectors_;
  std::vector<std::int32_t> states_;  // the visited states, permuted into the tree's leaves
  std::vector<Node> nodes_;           // nodes_[0] is the root
};

struct RunContext {
  const DiscreteEnvironment* env;
  const DiscreteProtocol* protocol;
  const JobSpec* job;
  std::int32_t run;
  kernels::SampleBatch batch;  // folded when the job asks for it
  kernels::EmpiricalTransitionModel model;
  std::int32_t graph_nodes;
  std::vector<std::int32_t> centers;      // centre order
  kernels::RowMatrixXd center_distances;  // rows: the first centres of `centers`
  std::vector<std::int32_t> nearest;
  std::vector<double> nearest_distance;
  std::vector<std::int32_t> visited_states;  // in id order
  // The run's graph diagnostics (kernels/graph_diagnostics.hpp).
  double edges = 0.0;
  double median_degree = 0.0;
  double geodesic_stretch = 0.0;
};

// kernel_gap of a fit: the mean over the visited states and the fit's centres of
// |K_GGK - K_OGK| at the fit's width (untruncated).
double fit_kernel_gap(const RunContext& ctx, std::span<const std::int32_t> centers, double sigma) {
  const auto& states = ctx.visited_states;
  const kernels::RowMatrixXd& vectors = ctx.env->state_vectors;
  std::vector<double> geodesic(states.size()), euclidean(states.size());
  double sum = 0.0;
  for (std::size_t j = 0; j < centers.size(); ++j) {
    for (std::size_t i = 0; i < states.size(); ++i) {
      geodesic[i] = ctx.center_distances(static_cast<Eigen::Index>(j), states[i]);
      euclidean[i] = state_distance(vectors, states[i], centers[j]);
    }
    sum += kernels::kernel_gap_sum(geodesic, euclidean, sigma);
  }
  const double pairs = static_cast<double>(states.size()) * static_cast<double>(centers.size());
  return pairs > 0.0 ? sum / pairs : kNaN;
}

// One greedy roll-out: the states visited (start first) and the steps taken to
// reach a goal, or -1 when none was reached within test_max_steps.
double roll_out(const RunContext& ctx, const std::vector<std::int32_t>& policy, std::int32_t start,
                kernels::RandomStream& random, std::vector<std::int32_t>* trajectory) {
  std::int32_t state = start;
  if (trajectory) trajectory->push_back(state);
  for (std::int32_t step = 1; step <= ctx.protocol->test_max_steps; ++step) {
    const Transition t = ctx.env->step(state, policy[static_cast<std::size_t>(state)], random);
    if (trajectory) trajectory->push_back(t.next_state);
    if (t.terminal) return step;
    state = t.next_state;
  }
  return -1.0;
}

// One test of a greedy policy (the protocol's test, sec. 4): a roll-out from every
// start state, then one from each named start, all from a fresh copy of the fit's
// evaluation stream (so the test of the last iterate is the fit's own test).
struct PolicyTest {
  double success = 0.0;       // fraction of start states that reach a goal
  double mean_steps = kNaN;   // over the successful roll-outs
  std::vector<double> steps;  // per start state, -1 when it did not arrive
  std::vector<double> named_steps;
  std::vector<std::vector<std::int32_t>> trajectories;  // per named start, when asked
};

PolicyTest test_policy(const RunContext& ctx, const SweepPoint& point,
                       const std::vector<std::int32_t>& policy, bool keep_trajectories) {
  const DiscreteEnvironment& env = *ctx.env;
  kernels::RandomStream random = stream_for(ctx.job->seed, ctx.run, Purpose::evaluation,
                                            static_cast<std::uint32_t>(point.evaluation_stream));
  PolicyTest test;
  test.steps.reserve(env.start_states.size());
  double successes = 0.0, step_sum = 0.0;
  for (std::int32_t start : env.start_states) {
    test.steps.push_back(roll_out(ctx, policy, start, random, nullptr));
    if (test.steps.back() >= 0) {
      successes += 1.0;
      step_sum += test.steps.back();
    }
  }
  for (const auto& named : env.named_starts) {
    std::vector<std::int32_t> trajectory;
    test.named_steps.push_back(
        roll_out(ctx, policy, named.second, random, keep_trajectories ? &trajectory : nullptr));
    if (keep_trajectories) test.trajectories.push_back(std::move(trajectory));
  }
  test.success = successes / static_cast<double>(test.steps.size());
  test.mean_steps = successes > 0 ? step_sum / successes : kNaN;
  return test;
}

// [lspi] evaluate_iterations: every iteration's weights (history/weights,
// iterations x k) and its greedy policy's test, one value per iteration, under the
// fit's metric names (history/success_rate, history/mean_steps_to_goal,
// history/success_from_A, ...). The last entries equal the fit's own metrics.
void add_iteration_tests(const RunContext& ctx, const SweepPoint& point,
                         const kernels::SparseRowMatrix& features, FitRecord& fit) {
  const DiscreteEnvironment& env = *ctx.env;
  const auto iterations = static_cast<std::int64_t>(fit.lspi.iterates.size());
  const auto k = static_cast<std::int64_t>(fit.lspi.iterates.front().size());
  NamedArray weights{"history/weights", {iterations, k}, {}};
  weights.values.reserve(static_cast<std::size_t>(iterations * k));
  std::vector<std::vector<double>> series(2 + 2 * env.named_starts.size());
  for (const Eigen::VectorXd& w : fit.lspi.iterates) {
    weights.values.insert(weights.values.end(), w.data(), w.data() + w.size());
    const PolicyTest test =
        test_policy(ctx, point, kernels::greedy_policy(features, env.num_actions, w), false);
    series[0].push_back(test.success);
    series[1].push_back(test.mean_steps);
    for (std::size_t i = 0; i < env.named_starts.size(); ++i) {
      const double steps = test.named_steps[i];
      series[2 + 2 * i].push_back(steps >= 0 ? 1.0 : 0.0);
      series[3 + 2 * i].push_back(steps >= 0 ? steps : kNaN);
    }
  }
  fit.arrays.push_back(std::move(weights));
  std::vector<std::string> names = {discrete_metric_names()[0], discrete_metric_names()[1]};
  for (const auto& named : env.named_starts) {
    names.push_back("success_from_" + named.first);
    names.push_back("steps_from_" + named.first);
  }
  for (std::size_t i = 0; i < names.size(); ++i) {
    fit.arrays.push_back({"history/" + names[i], {iterations}, std::move(series[i])});
  }
}

FitRecord fit_point(const RunContext& ctx, const SweepPoint& point) {
  const auto started = std::chrono::steady_clock::now();
  FitRecord fit;
  fit.point = point;
  const auto& names = discrete_metric_names();
  // Named starts add success_from_<name> and steps_from_<name>; without a
  // policy (invalid or failed fit) every metric but the graph size is NaN.
  double kernel_gap = kNaN;
  auto set_metrics = [&](double success, double mean_steps, double iterations,
                         const std::vector<double>& named_steps) {
    fit.metrics = {{names[0], success},
                   {names[1], mean_steps},
                   {names[2], iterations},
                   {names[3], static_cast<double>(ctx.graph_nodes)},
                   {names[4], ctx.edges},
                   {names[5], ctx.median_degree},
                   {names[6], ctx.geodesic_stretch},
                   {names[7], kernel_gap}};
    for (std::size_t i = 0; i < ctx.env->named_starts.size(); ++i) {
      const std::string& name = ctx.env->named_starts[i].first;
      const double steps = i < named_steps.size() ? named_steps[i] : kNaN;
      fit.metrics.emplace_back("success_from_" + name,
                               std::isnan(steps) ? kNaN : (steps >= 0 ? 1.0 : 0.0));
      fit.metrics.emplace_back("steps_from_" + name, steps >= 0 ? steps : kNaN);
    }
  };
  if (point.kernels > ctx.graph_nodes) {
    fit.status = "invalid";
    fit.message = "run " + std::to_string(ctx.run) + ": " + std::to_string(point.kernels) +
                  " kernels requested but the sample graph has only " +
                  std::to_string(ctx.graph_nodes) + " nodes";
    set_metrics(kNaN, kNaN, 0.0, {});
    return fit;
  }
  const DiscreteEnvironment& env = *ctx.env;
  fit.centers.assign(ctx.centers.begin(), ctx.centers.begin() + point.kernels);
  kernel_gap = fit_kernel_gap(ctx, fit.centers, point.sigma);
  const double truncation = ctx.job->basis.truncation;
  kernels::SparseRowMatrix state_kernels;
  if (point.basis == KernelType::ggk) {
    state_kernels = kernels::continuous_geodesic_gaussian_kernels(
        ctx.nearest, ctx.nearest_distance, ctx.center_distances.topRows(point.kernels), point.sigma,
        truncation);
  } else {
    kernels::RowMatrixXd center_vectors(point.kernels, env.state_vectors.cols());
    for (std::int32_t j = 0; j < point.kernels; ++j) {
      center_vectors.row(j) = env.state_vectors.row(fit.centers[static_cast<std::size_t>(j)]);
    }
    state_kernels = kernels::ordinary_gaussian_kernels(env.state_vectors, center_vectors,
                                                       point.sigma, truncation);
  }
  const kernels::SparseRowMatrix features =
      ctx.job->basis.scheme == kernels::BasisScheme::shift
          ? kernels::shift_basis(state_kernels, env.num_actions, ctx.model)
          : kernels::copy_basis(state_kernels, env.num_actions);

  fit.lspi = kernels::fit_lspi(features, env.num_actions, ctx.batch, lspi_options(point));
  fit.status = kernels::to_string(fit.lspi.status);
  fit.message = fit.lspi.message;

  if (fit.lspi.weights.size() == 0) {
    set_metrics(kNaN, kNaN, 0.0, {});
  } else {
    const PolicyTest test = test_policy(ctx, point, fit.lspi.policy, true);
    set_metrics(test.success, test.mean_steps, static_cast<double>(fit.lspi.iterations()),
                test.named_steps);
    for (std::size_t i = 0; i < env.named_starts.size(); ++i) {
      const std::vector<std::int32_t>& trajectory = test.trajectories[i];
      fit.arrays.push_back({"trajectory_" + env.named_starts[i].first,
                            {static_cast<std::int64_t>(trajectory.size())},
                            std::vector<double>(trajectory.begin(), trajectory.end()),
                            ElementType::kInt32});
    }
    fit.arrays.push_back({"steps_to_goal",
                          {static_cast<std::int64_t>(test.steps.size())},
                          test.steps,
                          ElementType::kInt32});
    const Eigen::VectorXd values =
        kernels::state_values(features, env.num_actions, fit.lspi.weights);
    fit.arrays.push_back({"state_values",
                          {static_cast<std::int64_t>(values.size())},
                          std::vector<double>(values.data(), values.data() + values.size())});
    if (!fit.lspi.iterates.empty()) add_iteration_tests(ctx, point, features, fit);
  }
  fit.fit_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  return fit;
}

}  // namespace

void nearest_visited_states(const kernels::RowMatrixXd& state_vectors,
                            const std::vector<std::uint8_t>& visited,
                            std::vector<std::int32_t>& nearest, std::vector<double>& distance) {
  const auto n = static_cast<std::int32_t>(state_vectors.rows());
  nearest.assign(static_cast<std::size_t>(n), 0);
  distance.assign(static_cast<std::size_t>(n), 0.0);
  std::vector<std::int32_t> visited_states;
  for (std::int32_t s = 0; s < n; ++s) {
    if (visited[static_cast<std::size_t>(s)]) {
      nearest[static_cast<std::size_t>(s)] = s;
      visited_states.push_back(s);
    }
  }
  if (visited_states.empty()) {
    std::fill(distance.begin(), distance.end(), std::numeric_limits<double>::infinity());
    return;
  }
  const VisitedStateTree tree(state_vectors, std::move(visited_states));
  tbb::parallel_for(tbb::blocked_range<std::int32_t>(0, n, 1024),
                    [&](const tbb::blocked_range<std::int32_t>& range) {
                      for (std::int32_t s = range.begin(); s < range.end(); ++s) {
                        if (visited[static_cast<std::size_t>(s)]) continue;
                        const auto [v, d] = tree.nearest(s);
                        nearest[static_cast<std::size_t>(s)] = v;
                        distance[static_cast<std::size_t>(s)] = d;
                      }
                    });
}

RunRecord run_discrete_protocol(const DiscreteEnvironment& env, const DiscreteProtocol& protocol,
                                const JobSpec& job, std::int32_t run,
                                std::span<const SweepPoint> points) {
  RunRecord record;
  record.run = run;

  kernels::RandomStream sample_stream = stream_for(job.seed, run, Purpose::samples);
  const kernels::SampleBatch raw = collect_samples(env, protocol, sample_stream);
  record.samples = to_sample_record(env, raw);

  // The graph the samples induce: nodes are states, edges observed transitions.
  std::vector<kernels::NodeTransition> transitions(raw.size());
  std::vector<std::uint8_t> visited(static_cast<std::size_t>(env.num_states), 0);
  for (std::size_t i = 0; i < raw.size(); ++i) {
    transitions[i] = {raw.states[i], raw.next_states[i]};
    visited[static_cast<std::size_t>(raw.states[i])] = 1;
    visited[static_cast<std::size_t>(raw.next_states[i])] = 1;
  }
  record.graph = kernels::transition_graph(env.state_vectors, transitions);
  record.node_states = env.state_vectors;
  record.arrays.push_back({"graph/visited",
                           {static_cast<std::int64_t>(visited.size())},
                           std::vector<double>(visited.begin(), visited.end()),
                           ElementType::kUInt8});

  // LSPI learns from the moves that start outside a goal: a walk that goes on
  // through goals (walk_through_goals) also records moves out of goals, which
  // belong to no episode and whose features (shift scheme) equal those of the
  // moves into the goal; they shape the graph only.
  kernels::SampleBatch episodic;
  std::vector<std::uint8_t> is_goal(static_cast<std::size_t>(env.num_states), 0);
  for (std::int32_t g : env.goal_states) is_goal[static_cast<std::size_t>(g)] = 1;
  for (std::size_t i = 0; i < raw.size(); ++i) {
    if (is_goal[static_cast<std::size_t>(raw.states[i])]) continue;
    episodic.add(raw.states[i], raw.actions[i], raw.rewards[i], raw.next_states[i],
                 raw.terminals[i] != 0, raw.weights[i]);
  }
  kernels::SampleBatch batch =
      job.lspi.fold_duplicates ? kernels::fold_duplicate_samples(episodic) : episodic;
  kernels::EmpiricalTransitionModel model(env.num_states, env.num_actions, batch.states,
                                          batch.actions, batch.next_states, batch.weights);
  RunContext ctx{&env, &protocol, &job, run, std::move(batch), std::move(model), 0, {}, {}, {}, {},
                 {},   0.0,       0.0,  0.0};
  ctx.graph_nodes =
      static_cast<std::int32_t>(std::count(visited.begin(), visited.end(), std::uint8_t{1}));
  kernels::RandomStream center_stream = stream_for(job.seed, run, Purpose::centers);
  ctx.centers = center_order(env, visited, center_stream);
  std::int32_t max_kernels = 0;
  for (const SweepPoint& p : points) max_kernels = std::max(max_kernels, p.kernels);
  const auto sources = std::span<const std::int32_t>(ctx.centers)
                           .first(static_cast<std::size_t>(std::min(max_kernels, ctx.graph_nodes)));
  ctx.center_distances = kernels::geodesic_distances(record.graph, sources);
  nearest_visited_states(env.state_vectors, visited, ctx.nearest, ctx.nearest_distance);
  for (std::int32_t s = 0; s < env.num_states; ++s) {
    if (visited[static_cast<std::size_t>(s)]) ctx.visited_states.push_back(s);
  }
  ctx.edges = static_cast<double>(kernels::undirected_edge_count(record.graph));
  ctx.median_degree = kernels::median_degree(record.graph, visited);
  ctx.geodesic_stretch =
      kernels::geodesic_stretch(ctx.center_distances, sources, env.state_vectors);

  record.fits.resize(points.size());
  tbb::parallel_for(std::size_t{0}, points.size(),
                    [&](std::size_t i) { record.fits[i] = fit_point(ctx, points[i]); });
  return record;
}

RunMemoryEstimate estimate_discrete_run(const DiscreteSizes& sizes,
                                        const DiscreteProtocol& protocol, const JobSpec& job) {
  const double states = sizes.states, d = sizes.state_dimension, m = sizes.actions;
  const double n = static_cast<double>(protocol.series) * protocol.steps_per_series;
  // Distinct (s, a, s') moves: at most the samples, and at most every state's
  // moves with their successors. Only they survive folding.
  const double moves = std::min(n, states * m * sizes.successors);
  const double batch = job.lspi.fold_duplicates ? moves : n;
  const std::vector<SweepPoint> points = expand_sweep(job);
  double max_kernels = 0.0;
  for (const SweepPoint& p : points) max_kernels = std::max<double>(max_kernels, p.kernels);
  max_kernels = std::min(max_kernels, states);  // a fit with more kernels than nodes never starts

  RunMemoryEstimate estimate;
  // Samples: the raw walk and its copy in the record (observations as state
  // vectors), the graph's transition list; then first the graph's edge lists,
  // and once they are freed the episodic batch, the folding's hash map, the
  // folded batch and the transition model built from it (sort order, successors).
  const double record_samples = n * (2.0 * d * 8.0 + 13.0);
  const double after_graph = sample_batch_bytes(n) +
                             (job.lspi.fold_duplicates ? folding_bytes(n, moves) : 0.0) +
                             sample_batch_bytes(batch) + batch * 20.0;
  estimate.add(count_text(n) + " samples per run (series x steps_per_series)",
               sample_batch_bytes(n) + record_samples + n * 8.0 +
                   std::max(graph_building_bytes(n), after_graph));
  // Per state: its vector (twice: environment and record), start list, visited
  // flags (and as doubles in the record), goal flags, nearest visited state and
  // distance, centre order, the visited-state list, the transition model's row
  // offsets.
  estimate.add(
      count_text(states) + " " + sizes.states_are,
      sizes.simulator_bytes + states * (16.0 * d + 46.0 + 8.0 * m) + graph_bytes(moves, states));
  estimate.add("the geodesic distances from " + count_text(max_kernels) + " centres to " +
                   count_text(states) + " states",
               max_kernels * states * 8.0);
  estimate.add_per_fit("the kernel and feature tables of a fit with " + count_text(max_kernels) +
                           " kernels (" + count_text(states) + " states x " + count_text(m) +
                           " actions)",
                       // + the kernel gap's two distance rows (states doubles each)
                       kernel_and_feature_bytes(states, max_kernels, m) + states * (m + 3.0) * 8.0);
  estimate.add_per_fit("the LSPI system of a fit with " + count_text(m) + " x " +
                           count_text(max_kernels) + " basis functions",
                       lspi_bytes(states, max_kernels, m, batch));
  // The fits' results: LSPI systems, policies, values, and the named starts'
  // trajectories (test_max_steps + 1 states each when the goal is not reached).
  double fits = 0.0;
  for (const SweepPoint& p : points) {
    fits += fit_record_bytes(states, std::min<double>(p.kernels, states), m,
                             p.solver == kernels::LspiSolver::brm) +
            sizes.named_starts * (protocol.test_max_steps + 1.0) * 12.0;
  }
  estimate.add("the results of " + count_text(static_cast<double>(points.size())) + " fits", fits);
  estimate.record_bytes =
      record_samples + graph_bytes(moves, states) + states * (d + 1.0) * 8.0 + fits;
  return estimate;
}

}  // namespace ggk::engine
