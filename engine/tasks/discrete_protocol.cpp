#include "engine/tasks/discrete_protocol.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <numeric>
#include <string>
#include <utility>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "engine/tasks/fit_count.hpp"
#include "engine/tasks/pvf_basis.hpp"
#include "engine/tasks/seeds.hpp"
#include "kernels/gaussian_kernels.hpp"
#include "kernels/graph_diagnostics.hpp"
#include "kernels/nearest_visited.hpp"
#include "kernels/state_action_table.hpp"
#include "kernels/transition_model.hpp"

namespace ggk::engine {

namespace {

// The goal test's metrics (its roll-outs take test_max_steps steps at most).
std::vector<MetricSpec> goal_test_specs(const DiscreteProtocol& protocol) {
  return {tested(fraction_metric("success_rate",
                                 "share of the start states from which the greedy policy reaches "
                                 "a goal within test_max_steps")),
          tested(mean_metric("mean_steps_to_goal", "steps",
                             "mean steps to a goal over the start states that reach one", 0.0,
                             protocol.test_max_steps))};
}

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

// Euclidean distance between the state vectors of states a and b, as
// kernels::nearest_visited_states computes it.
double state_distance(const kernels::RowMatrixXd& vectors, std::int32_t a, std::int32_t b) {
  return (vectors.row(a) - vectors.row(b)).norm();
}

struct RunContext {
  const DiscreteEnvironment* env = nullptr;
  const DiscreteProtocol* protocol = nullptr;
  const JobSpec* job = nullptr;
  std::int32_t run = 0;
  kernels::SampleBatch batch;  // folded when the job asks for it
  std::unique_ptr<kernels::EmpiricalTransitionModel> model;
  RunGraph graph;
  RunEigenbases eigenbases;         // the proto-value functions, when a point asks
  std::vector<MetricSpec> metrics;  // discrete_metric_specs(*env, *protocol)
  std::vector<std::int32_t> nearest;
  std::vector<double> nearest_distance;
  std::vector<std::int32_t> visited_states;  // in id order
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
      geodesic[i] = ctx.graph.center_distances(static_cast<Eigen::Index>(j), states[i]);
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

// The goal test of a greedy policy (the protocol's test, sec. 4): a roll-out from
// every start state, then one from each named start, all from a fresh copy of the
// run's evaluation stream (seeds.hpp: every fit and iterate of a run meets the
// same noise, so the test of the last iterate is the fit's own test).
struct GoalTest {
  double success = 0.0;       // fraction of start states that reach a goal
  double mean_steps = kNaN;   // over the successful roll-outs
  std::vector<double> steps;  // per start state, -1 when it did not arrive
  std::vector<double> named_steps;
  std::vector<std::vector<std::int32_t>> trajectories;  // per named start, when asked
};

GoalTest goal_test(const RunContext& ctx, const std::vector<std::int32_t>& policy,
                   bool keep_trajectories) {
  const DiscreteEnvironment& env = *ctx.env;
  kernels::RandomStream random = stream_for(ctx.job->seed, ctx.run, Purpose::evaluation);
  GoalTest test;
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

// Sets the tested metrics of `policy`: the task's own test, or the goal test's
// metrics (its record in *kept when asked, with the named starts' trajectories).
void test_greedy_policy(const RunContext& ctx, const std::vector<std::int32_t>& policy,
                        FitMetrics& metrics, GoalTest* kept) {
  const DiscreteEnvironment& env = *ctx.env;
  if (env.test_policy) {
    env.test_policy(policy, metrics);
    return;
  }
  GoalTest test = goal_test(ctx, policy, kept != nullptr);
  metrics.set("success_rate", test.success);
  metrics.set("mean_steps_to_goal", test.mean_steps);
  for (std::size_t i = 0; i < env.named_starts.size(); ++i) {
    const std::string& name = env.named_starts[i].first;
    const double steps = test.named_steps[i];
    metrics.set("success_from_" + name, steps >= 0 ? 1.0 : 0.0);
    metrics.set("steps_from_" + name, steps >= 0 ? steps : kNaN);
  }
  if (kept != nullptr) *kept = std::move(test);
}

// Without a policy (invalid or failed fit) every metric but the run's graph
// metrics is NaN and lspi_iterations is 0.
FitRecord fit_point(const RunContext& ctx, const SweepPoint& point) {
  const auto started = std::chrono::steady_clock::now();
  if (point.kernels > ctx.graph.nodes) {
    return invalid_fit(point, ctx.run, ctx.graph, ctx.metrics,
                       "the sample graph has only " + std::to_string(ctx.graph.nodes) + " nodes");
  }
  const bool pvf = point.basis == KernelType::pvf;
  if (pvf && !ctx.eigenbases.of(point.kernels).ok) {
    return invalid_fit(
        point, ctx.run, ctx.graph, ctx.metrics,
        "the Laplacian's eigenpairs are missing: " + ctx.eigenbases.of(point.kernels).message);
  }
  FitMetrics metrics(ctx.metrics);
  metrics.set("lspi_iterations", 0.0);
  const DiscreteEnvironment& env = *ctx.env;
  FitRecord fit;
  fit.point = point;
  // A PVF fit has no centres and no kernel gap (NaN); it keeps its eigenvalues.
  if (!pvf) {
    fit.centers.assign(ctx.graph.centers.begin(), ctx.graph.centers.begin() + point.kernels);
  } else {
    fit.arrays.push_back(eigenvalue_array(ctx.eigenbases.of(point.kernels)));
    fit.warning = eigenbasis_warning(ctx.eigenbases.of(point.kernels));
  }
  set_graph_metrics(metrics, ctx.graph, pvf ? kNaN : fit_kernel_gap(ctx, fit.centers, point.sigma));
  const double truncation = ctx.job->basis.truncation;
  kernels::SparseRowMatrix state_kernels;
  if (pvf) {
    state_kernels = pvf_state_table(ctx.eigenbases.of(point.kernels), ctx.nearest, point.kernels);
  } else {
    try {
      if (point.basis == KernelType::ggk) {
        state_kernels = kernels::continuous_geodesic_gaussian_kernels(
            ctx.nearest, ctx.nearest_distance, ctx.graph.center_distances.topRows(point.kernels),
            point.sigma, truncation);
      } else {
        kernels::RowMatrixXd center_vectors(point.kernels, env.state_vectors.cols());
        for (std::int32_t j = 0; j < point.kernels; ++j) {
          center_vectors.row(j) = env.state_vectors.row(fit.centers[static_cast<std::size_t>(j)]);
        }
        state_kernels = kernels::ordinary_gaussian_kernels(env.state_vectors, center_vectors,
                                                           point.sigma, truncation);
      }
    } catch (const kernels::NonFiniteKernelValue& e) {
      throw non_finite_kernel_error(ctx.run, point, e);
    }
  }
  // Read through the state kernels' rows where the table is made of them (the
  // copy scheme, the arm's deterministic shift scheme), else formed: the same fit.
  const kernels::BasisScheme scheme = pvf ? ctx.job->pvf.actions : ctx.job->basis.scheme;
  const kernels::StateActionTable features(state_kernels, env.num_actions, scheme, ctx.model.get());

  fit.lspi = features.fit(ctx.batch, lspi_options(point));
  fit.status = kernels::to_string(fit.lspi.status);
  fit.message = fit.lspi.message;

  if (fit.lspi.weights.size() != 0) {
    metrics.set("lspi_iterations", static_cast<double>(fit.lspi.iterations()));
    GoalTest test;
    test_greedy_policy(ctx, fit.lspi.policy, metrics, &test);
    for (std::size_t i = 0; i < test.trajectories.size(); ++i) {
      const std::vector<std::int32_t>& trajectory = test.trajectories[i];
      fit.arrays.push_back({"trajectory_" + env.named_starts[i].first,
                            {static_cast<std::int64_t>(trajectory.size())},
                            std::vector<double>(trajectory.begin(), trajectory.end()),
                            ElementType::kInt32});
    }
    if (!env.test_policy) {
      fit.arrays.push_back({"steps_to_goal",
                            {static_cast<std::int64_t>(test.steps.size())},
                            test.steps,
                            ElementType::kInt32});
    }
    const Eigen::VectorXd values = features.values(fit.lspi.weights);
    fit.arrays.push_back({"state_values",
                          {static_cast<std::int64_t>(values.size())},
                          std::vector<double>(values.data(), values.data() + values.size())});
    if (!fit.lspi.iterates.empty()) {
      // [lspi] evaluate_iterations: history/<tested metric> per iterate.
      add_iteration_history(fit, ctx.metrics, [&](const Eigen::VectorXd& w, FitMetrics& iterate) {
        test_greedy_policy(ctx, features.greedy(w), iterate, nullptr);
      });
    }
  }
  fit.metrics = metrics.named_values();
  fit.fit_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  return fit;
}

}  // namespace

std::vector<MetricSpec> discrete_metric_specs(std::span<const MetricSpec> policy_metrics,
                                              std::span<const std::string> named_starts,
                                              const DiscreteProtocol& protocol) {
  std::vector<MetricSpec> specs(policy_metrics.begin(), policy_metrics.end());
  if (specs.empty()) specs = goal_test_specs(protocol);
  specs.insert(specs.end(), graph_metric_specs().begin(), graph_metric_specs().end());
  for (const std::string& name : named_starts) {
    specs.push_back(tested(indicator_metric(
        "success_from_" + name,
        "1 when the greedy policy reaches a goal from start " + name + " within test_max_steps")));
    specs.push_back(
        tested(mean_metric("steps_from_" + name, "steps",
                           "steps to a goal from start " + name + " (NaN when it does not arrive)",
                           0.0, protocol.test_max_steps)));
  }
  return specs;
}

std::vector<MetricSpec> discrete_metric_specs(const DiscreteEnvironment& env,
                                              const DiscreteProtocol& protocol) {
  std::vector<std::string> named_starts;
  for (const auto& named : env.named_starts) named_starts.push_back(named.first);
  return discrete_metric_specs(env.test_policy ? std::span<const MetricSpec>(env.policy_metrics)
                                               : std::span<const MetricSpec>(),
                               named_starts, protocol);
}

const std::vector<std::string>& discrete_metric_names() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> result;
    for (const MetricSpec& spec :
         discrete_metric_specs(DiscreteEnvironment{}, DiscreteProtocol{})) {
      result.push_back(spec.name);
    }
    return result;
  }();
  return names;
}

RunRecord run_discrete_protocol(const DiscreteEnvironment& env, const DiscreteProtocol& protocol,
                                const JobSpec& job, std::int32_t run,
                                std::span<const SweepPoint> points) {
  RunRecord record;
  record.run = run;
  record.action_names = env.action_names;
  record.metric_specs = discrete_metric_specs(env, protocol);
  if (!env.test_policy) {  // the states steps_to_goal indexes
    record.arrays.push_back({"start_states",
                             {static_cast<std::int64_t>(env.start_states.size())},
                             std::vector<double>(env.start_states.begin(), env.start_states.end()),
                             ElementType::kInt32});
  }

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
  RunContext ctx;
  ctx.env = &env;
  ctx.protocol = &protocol;
  ctx.job = &job;
  ctx.run = run;
  ctx.batch = job.lspi.fold_duplicates ? kernels::fold_duplicate_samples(episodic) : episodic;
  ctx.model = std::make_unique<kernels::EmpiricalTransitionModel>(
      env.num_states, env.num_actions, ctx.batch.states, ctx.batch.actions, ctx.batch.next_states,
      ctx.batch.weights);
  kernels::RandomStream center_stream = stream_for(job.seed, run, Purpose::centers);
  ctx.graph = run_graph(record.graph, visited, center_order(env, visited, center_stream),
                        env.state_vectors, points);
  ctx.eigenbases = run_eigenbases(record.graph, visited, job.pvf, points);
  ctx.metrics = record.metric_specs;
  kernels::nearest_visited_states(env.state_vectors, visited, ctx.nearest, ctx.nearest_distance);
  for (std::int32_t s = 0; s < env.num_states; ++s) {
    if (visited[static_cast<std::size_t>(s)]) ctx.visited_states.push_back(s);
  }

  record.fits.resize(points.size());
  tbb::parallel_for(std::size_t{0}, points.size(), [&](std::size_t i) {
    record.fits[i] = fit_point(ctx, points[i]);
    count_fit_done();
  });
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
  double pvf_vectors = 0.0;  // every count's eigenvectors (pvf_basis.hpp), counts <= states
  for (const std::int32_t count :
       pvf_counts(points, static_cast<std::int32_t>(std::min<double>(states, 2147483647.0)))) {
    pvf_vectors += count;
  }
  if (pvf_vectors > 0.0) {
    // The Laplacian (an entry per arc and node), its eigenvectors over the nodes
    // and spread over the states, the solver's Lanczos basis (at most 2 P + 20
    // vectors) and CHOLMOD's factor (bounded by the Laplacian's fill; taken as
    // ten times its entries).
    estimate.add("the proto-value functions (" + count_text(pvf_vectors) + " eigenvectors of " +
                     count_text(states) + " nodes)",
                 states * (2.0 * pvf_vectors + 2.0 * pvf_vectors + 20.0) * 8.0 +
                     11.0 * (2.0 * moves + states) * 12.0);
  }
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

std::vector<DatasetSpecs> discrete_dataset_specs(std::span<const DatasetSpecs> own) {
  static constexpr std::array kDiscreteDatasets = {
      DatasetSpec{"start_states", "start", "node id",
                  "the states the goal test starts from, the index of steps_to_goal (maze, arm)"},
      DatasetSpec{"graph/visited", "node", "flag",
                  "1 if a sample starts or ends there (maze, arm)"},
      DatasetSpec{"fit:state_values", "state", "return", "V(s) = max_a Q(s, a)"},
      DatasetSpec{"fit:steps_to_goal", "start", "steps",
                  "greedy steps from each of start_states to a goal, -1 = failed"},
      DatasetSpec{"fit:trajectory_*", "step", "node id",
                  "the states of the greedy walk from the named start, the start first"},
  };
  std::vector<DatasetSpecs> specs(own.begin(), own.end());
  specs.push_back({"discrete tasks", kDiscreteDatasets});
  specs.push_back(graph_dataset_specs());
  return specs;
}

}  // namespace ggk::engine
