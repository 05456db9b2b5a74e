#include "engine/tasks/continuous_protocol.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <tuple>
#include <utility>

#include <tbb/parallel_for.h>

#include "engine/tasks/continuous_episodes.hpp"
#include "engine/tasks/fit_count.hpp"
#include "engine/tasks/pvf_basis.hpp"
#include "engine/tasks/seeds.hpp"
#include "kernels/action_block_system.hpp"
#include "kernels/gaussian_kernels.hpp"
#include "kernels/graph_diagnostics.hpp"
#include "kernels/lspi.hpp"
#include "kernels/state_action_table.hpp"
#include "kernels/transition_model.hpp"

namespace ggk::engine {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// The kernel gap's sum over the observations per centre (in centre order) for one width.
struct SharedGap {
  double sigma = 0.0;
  std::vector<double> per_center;
};

// Everything the fits of a run share.
struct RunContext {
  const ContinuousEnvironment* env = nullptr;
  const ContinuousProtocol* protocol = nullptr;
  const JobSpec* job = nullptr;
  std::int32_t run = 0;
  std::vector<MetricSpec> specs;
  kernels::RowMatrixXd observations;  // the walks' observations, scaled
  const kernels::SelfOrganizingMap* som = nullptr;
  kernels::BestMatches state_units;    // best-matching unit of every observation
  RunGraph graph;                      // over the occupied units, centres among them
  RunEigenbases eigenbases;            // the proto-value functions, when a point asks
  std::vector<std::uint8_t> occupied;  // per unit: the best match of some observation
  kernels::SampleBatch batch;          // the walks' samples, folded if the job asks
  std::unique_ptr<kernels::EmpiricalTransitionModel> model;  // for the shift scheme
  // The kernel gap's per-centre sums, per width (formed before the fits start).
  std::vector<SharedGap> kernel_gaps;
};

// kernel_gap of a fit: the mean over the walks' observations and the fit's
// centres of |K_GGK - K_OGK| at the fit's width (untruncated), GGK in the
// continuous form the fit's kernel table uses.
// The kernel gap's sum over the observations for each of `centers` (one term per centre).
std::vector<double> kernel_gap_terms(const RunContext& ctx, std::span<const std::int32_t> centers,
                                     double sigma) {
  const kernels::RowMatrixXd& observations = ctx.observations;
  const auto n = static_cast<std::size_t>(observations.rows());
  std::vector<double> terms(centers.size());
  tbb::parallel_for(std::size_t{0}, centers.size(), [&](std::size_t j) {
    std::vector<double> geodesic(n), euclidean(n);
    const auto center = ctx.som->prototypes().row(centers[j]);
    for (std::size_t i = 0; i < n; ++i) {
      const auto row = static_cast<Eigen::Index>(i);
      geodesic[i] =
          ctx.state_units.distances[i] +
          ctx.graph.center_distances(static_cast<Eigen::Index>(j), ctx.state_units.units[i]);
      euclidean[i] = (observations.row(row) - center).norm();
    }
    terms[j] = kernels::kernel_gap_sum(geodesic, euclidean, sigma);
  });
  return terms;
}

// The mean of the first p terms over the observations (summed in centre order).
double fit_kernel_gap(const RunContext& ctx, std::int32_t p, double sigma) {
  const SharedGap* gap = nullptr;
  for (const SharedGap& g : ctx.kernel_gaps) {
    if (g.sigma == sigma) gap = &g;
  }
  double sum = 0.0;
  for (std::int32_t j = 0; j < p; ++j) sum += gap->per_center[static_cast<std::size_t>(j)];
  const double pairs = static_cast<double>(ctx.observations.rows()) * static_cast<double>(p);
  return pairs > 0.0 ? sum / pairs : kNaN;
}

// The state kernels of every observation of the walks for the first p centres.
// row_of_state is empty (one row per observation) except for proto-value
// functions in the copy scheme: their observations take their SOM unit's row, so
// `kernels` holds each occupied unit's row once (pvf_row_table) for
// fit_lspi_pooled_copy_basis, whose system sums over the distinct (unit, action)
// and (action, successor unit) pairs instead of the readings and whose greedy step
// reads each unit once.
struct FitTable {
  kernels::SparseRowMatrix kernels;
  std::vector<std::int32_t> row_of_state;
};

// base: the GGK or OGK table of this basis and sigma for at least p centres (the
// sweep's largest count, kernel_bases): its leading p columns, bit for bit the
// table of p centres; null: built here.
FitTable state_kernel_table(const RunContext& ctx, KernelType basis, double sigma, std::int32_t p,
                            const kernels::SparseRowMatrix* base = nullptr) {
  const double truncation = ctx.job->basis.truncation;
  if (base != nullptr && basis != KernelType::pvf) {
    return {kernels::leading_columns(*base, p), {}};
  }
  if (basis == KernelType::pvf) {
    if (ctx.job->pvf.actions == kernels::BasisScheme::copy) {
      PvfRowTable table = pvf_row_table(ctx.eigenbases.of(p), ctx.state_units.units, p);
      return {std::move(table.rows), std::move(table.row_of_state)};
    }
    return {pvf_state_table(ctx.eigenbases.of(p), ctx.state_units.units, p), {}};
  }
  if (basis == KernelType::ggk) {
    return {kernels::continuous_geodesic_gaussian_kernels(
                ctx.state_units.units, ctx.state_units.distances,
                ctx.graph.center_distances.topRows(p), sigma, truncation),
            {}};
  }
  kernels::RowMatrixXd center_vectors(p, ctx.observations.cols());
  for (std::int32_t j = 0; j < p; ++j) {
    center_vectors.row(j) =
        ctx.som->prototypes().row(ctx.graph.centers[static_cast<std::size_t>(j)]);
  }
  return {kernels::ordinary_gaussian_kernels(ctx.observations, center_vectors, sigma, truncation),
          {}};
}

// The test of greedy weights: the episodes from a fresh copy of the run's
// evaluation stream (seeds.hpp: every fit of a run meets the same test noise);
// sets the tested metrics.
EpisodeTest test_weights(const RunContext& ctx, const ObservationKernels& kernels_of,
                         const Eigen::VectorXd& weights, FitMetrics& metrics,
                         bool keep_trajectories) {
  EpisodeTest test = test_episodes(*ctx.env, *ctx.protocol,
                                   stream_for(ctx.job->seed, ctx.run, Purpose::evaluation),
                                   kernels_of, weights, keep_trajectories);
  metrics.set("mean_return", test.mean_return);
  metrics.set(ctx.env->ended_metric, test.ended_fraction);
  metrics.set("mean_steps", test.mean_steps);
  return test;
}

// table: the point's state kernels (state_kernel_table), read only when the point
// is valid (no more kernels than graph nodes); shared: the copy basis's fixed
// part for table.kernels (null: the fit forms its own).
FitRecord fit_point(const RunContext& ctx, const SweepPoint& point, const FitTable& table,
                    const std::shared_ptr<const kernels::ActionBlockFixed>& shared) {
  const auto started = std::chrono::steady_clock::now();
  const std::int32_t m = ctx.env->num_actions;
  if (point.kernels > ctx.graph.nodes) {
    return invalid_fit(point, ctx.run, ctx.graph, ctx.specs,
                       "only " + std::to_string(ctx.graph.nodes) + " SOM units hold samples");
  }
  const bool pvf = point.basis == KernelType::pvf;
  if (pvf && !ctx.eigenbases.of(point.kernels).ok) {
    return invalid_fit(
        point, ctx.run, ctx.graph, ctx.specs,
        "the Laplacian's eigenpairs are missing: " + ctx.eigenbases.of(point.kernels).message);
  }
  FitMetrics metrics(ctx.specs);
  FitRecord fit;
  fit.point = point;
  // A PVF fit has no centres and no kernel gap (NaN); it keeps its eigenvalues.
  if (!pvf) {
    fit.centers.assign(ctx.graph.centers.begin(), ctx.graph.centers.begin() + point.kernels);
  } else {
    fit.arrays.push_back(eigenvalue_array(ctx.eigenbases.of(point.kernels)));
    fit.warning = eigenbasis_warning(ctx.eigenbases.of(point.kernels));
  }
  set_graph_metrics(metrics, ctx.graph,
                    pvf ? kNaN : fit_kernel_gap(ctx, point.kernels, point.sigma));

  // The copy scheme's table is never formed: fit_lspi_copy_basis reads the state
  // kernels (the same result bit for bit).
  const kernels::BasisScheme scheme = pvf ? ctx.job->pvf.actions : ctx.job->basis.scheme;
  if (scheme == kernels::BasisScheme::shift) {
    fit.lspi = kernels::StateActionTable(table.kernels, m, scheme, ctx.model.get())
                   .fit(ctx.batch, lspi_options(point));
  } else if (table.row_of_state.empty()) {
    fit.lspi =
        kernels::fit_lspi_copy_basis(table.kernels, m, ctx.batch, lspi_options(point), shared);
  } else {
    fit.lspi = kernels::fit_lspi_pooled_copy_basis(table.kernels, table.row_of_state, m, ctx.batch,
                                                   lspi_options(point));
  }
  fit.status = kernels::to_string(fit.lspi.status);
  fit.message = fit.lspi.message;
  metrics.set("lspi_iterations", static_cast<double>(fit.lspi.iterations()));
  if (fit.lspi.weights.size() == 0) {
    fit.metrics = metrics.named_values();
    return fit;
  }

  const ObservationKernels kernels_of(
      *ctx.som, ctx.occupied, ctx.graph.center_distances, point, fit.centers,
      ctx.job->basis.truncation, pvf ? &ctx.eigenbases.of(point.kernels).node_values : nullptr);
  EpisodeTest test;
  try {
    test = test_weights(ctx, kernels_of, fit.lspi.weights, metrics, true);
  } catch (const EnvironmentError& error) {
    // The environment failed in the test: the fit has weights but no test.
    fit.status = "environment_failed";
    fit.message = "run " + std::to_string(ctx.run) + ": " + error.what();
    fit.metrics = metrics.named_values();
    return fit;
  }
  fit.metrics = metrics.named_values();
  for (NamedArray& trajectory : test.trajectories) fit.arrays.push_back(std::move(trajectory));
  fit.arrays.push_back(
      {"evaluation/returns", {static_cast<std::int64_t>(test.returns.size())}, test.returns});
  if (!fit.lspi.iterates.empty()) {
    // [lspi] evaluate_iterations: history/<tested metric> per iterate.
    add_iteration_history(fit, ctx.specs, [&](const Eigen::VectorXd& w, FitMetrics& iterate) {
      test_weights(ctx, kernels_of, w, iterate, false);
    });
  }

  // The greedy action at every SOM unit's prototype (the paper's Fig. 5).
  NamedArray unit_policy{"unit_policy", {ctx.som->num_units()}, {}, ElementType::kInt32};
  for (std::int32_t u = 0; u < ctx.som->num_units(); ++u) {
    const auto row = ctx.som->prototypes().row(u);
    const std::vector<double> prototype(row.data(), row.data() + row.size());
    unit_policy.values.push_back(greedy_action(fit.lspi.weights, kernels_of(prototype), m));
  }
  fit.arrays.push_back(std::move(unit_policy));
  fit.fit_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  return fit;
}

// The fits of a run. The fits of one (basis, width, kernel count) differ only in
// the solver: they share one state-kernel table (built once, freed when they are
// done, so sharing never holds more tables than a table per fit would) and, in
// the copy scheme, their system's fixed part (D_a and the start right-hand side,
// formed once instead of once per solver, the same sums bit for bit). The
// kernel gap's per-centre sums are formed first, once per width, for the largest
// valid count.
// The GGK or OGK table of the largest valid kernel count of one basis and sigma
// among a run's points: the other counts' tables are its leading columns.
struct KernelBase {
  SweepPoint point;  // of the largest count
  kernels::SparseRowMatrix table;
};

// One KernelBase per (basis, sigma) of the GGK and OGK points with at most as many
// kernels as graph nodes, built in parallel: one table of the largest count's
// columns instead of one per count (the Khepera's OGK: 100 columns of exp per run
// instead of 550).
std::vector<KernelBase> kernel_bases(const RunContext& ctx, std::span<const SweepPoint> points) {
  std::vector<KernelBase> bases;
  for (const SweepPoint& point : points) {
    if (point.basis == KernelType::pvf || point.kernels > ctx.graph.nodes) continue;
    const auto it = std::find_if(bases.begin(), bases.end(), [&](const KernelBase& b) {
      return b.point.basis == point.basis && b.point.sigma == point.sigma;
    });
    if (it == bases.end()) {
      bases.push_back({point, {}});
    } else if (point.kernels > it->point.kernels) {
      it->point = point;
    }
  }
  tbb::parallel_for(std::size_t{0}, bases.size(), [&](std::size_t i) {
    KernelBase& base = bases[i];
    try {
      base.table =
          state_kernel_table(ctx, base.point.basis, base.point.sigma, base.point.kernels).kernels;
    } catch (const kernels::NonFiniteKernelValue& e) {
      throw non_finite_kernel_error(ctx.run, base.point, e);
    }
    base.table.makeCompressed();
  });
  return bases;
}

std::vector<FitRecord> fit_points(RunContext& ctx, std::span<const SweepPoint> points) {
  for (const SweepPoint& point : points) {
    if (point.kernels > ctx.graph.nodes || point.basis == KernelType::pvf) continue;
    const auto kernels = static_cast<std::size_t>(point.kernels);
    bool found = false;
    for (SharedGap& g : ctx.kernel_gaps) {
      if (g.sigma == point.sigma) {
        g.per_center.resize(std::max(g.per_center.size(), kernels));
        found = true;
      }
    }
    if (!found) ctx.kernel_gaps.push_back({point.sigma, std::vector<double>(kernels)});
  }
  for (SharedGap& g : ctx.kernel_gaps) {
    g.per_center = kernel_gap_terms(
        ctx, std::span<const std::int32_t>(ctx.graph.centers).first(g.per_center.size()), g.sigma);
  }
  std::vector<std::vector<std::size_t>> groups;
  for (std::size_t i = 0; i < points.size(); ++i) {
    auto same = [&](const std::vector<std::size_t>& group) {
      const SweepPoint& q = points[group.front()];
      return q.basis == points[i].basis && q.sigma == points[i].sigma &&
             q.kernels == points[i].kernels;
    };
    const auto it = std::find_if(groups.begin(), groups.end(), same);
    if (it == groups.end()) {
      groups.push_back({i});
    } else {
      it->push_back(i);
    }
  }
  std::vector<KernelBase> bases = kernel_bases(ctx, points);
  // The groups that take their table from each base: the last to take it frees it
  // (its fits no longer need the largest count's table beside their own).
  auto base_of = [&](const SweepPoint& point) {
    return std::find_if(bases.begin(), bases.end(), [&](const KernelBase& b) {
      return b.point.basis == point.basis && b.point.sigma == point.sigma;
    });
  };
  std::vector<std::atomic<std::int32_t>> base_users(bases.size());
  for (const std::vector<std::size_t>& group : groups) {
    const SweepPoint& first = points[group.front()];
    const auto base = base_of(first);
    if (base != bases.end() && first.kernels <= ctx.graph.nodes) {
      ++base_users[static_cast<std::size_t>(base - bases.begin())];
    }
  }
  std::vector<FitRecord> fits(points.size());
  tbb::parallel_for(std::size_t{0}, groups.size(), [&](std::size_t g) {
    const std::vector<std::size_t>& group = groups[g];
    const SweepPoint& first = points[group.front()];
    const auto base = base_of(first);
    FitTable table;
    if (first.kernels <= ctx.graph.nodes) {
      if (base == bases.end()) {
        try {
          table = state_kernel_table(ctx, first.basis, first.sigma, first.kernels);
        } catch (const kernels::NonFiniteKernelValue& e) {
          throw non_finite_kernel_error(ctx.run, first, e);
        }
      } else {
        table = state_kernel_table(ctx, first.basis, first.sigma, first.kernels, &base->table);
        if (--base_users[static_cast<std::size_t>(base - bases.begin())] == 0) {
          base->table = kernels::SparseRowMatrix();
        }
      }
    }
    const kernels::BasisScheme scheme =
        first.basis == KernelType::pvf ? ctx.job->pvf.actions : ctx.job->basis.scheme;
    std::shared_ptr<const kernels::ActionBlockFixed> shared;
    if (group.size() > 1 && first.kernels <= ctx.graph.nodes &&
        scheme == kernels::BasisScheme::copy && table.row_of_state.empty() &&
        table.kernels.isCompressed()) {
      shared = kernels::ActionBlockSystem::copy_basis_fixed(table.kernels, ctx.env->num_actions,
                                                            ctx.batch);
    }
    tbb::parallel_for(std::size_t{0}, group.size(), [&](std::size_t f) {
      fits[group[f]] = fit_point(ctx, points[group[f]], table, shared);
      count_fit_done();
    });
  });
  return fits;
}

NamedArray matrix_array(std::string name, const kernels::RowMatrixXd& matrix) {
  return {std::move(name),
          {matrix.rows(), matrix.cols()},
          std::vector<double>(matrix.data(), matrix.data() + matrix.size())};
}

}  // namespace

std::vector<MetricSpec> continuous_metric_specs(const ContinuousEnvironment& env,
                                                const ContinuousProtocol& protocol) {
  const double most_steps = protocol.test_max_steps;
  // An episode takes 1 .. test_max_steps steps: its return lies between the
  // least and the most that many rewards can sum to (0 included).
  double least_return = std::min(0.0, most_steps * env.reward_low);
  double most_return = std::max(0.0, most_steps * env.reward_high);
  if (env.return_range) {
    std::tie(least_return, most_return) = env.return_range(protocol.test_max_steps);
  }
  std::vector<MetricSpec> specs = {
      tested(mean_metric("mean_return", "1",
                         "mean over the test episodes of the greedy policy's summed rewards",
                         std::isnan(least_return) ? -kUnbounded : least_return,
                         std::isnan(most_return) ? kUnbounded : most_return)),
      tested(fraction_metric(env.ended_metric,
                             "share of the test episodes that ended (terminal or stopped) within "
                             "test_max_steps")),
      tested(
          mean_metric("mean_steps", "steps", "mean steps of the test episodes", 0.0, most_steps))};
  specs.insert(specs.end(), graph_metric_specs().begin(), graph_metric_specs().end());
  return specs;
}

RunRecord run_continuous_protocol(const ContinuousEnvironment& env,
                                  const ContinuousProtocol& protocol, const JobSpec& job,
                                  std::int32_t run, std::span<const SweepPoint> points) {
  RunContext ctx;
  ctx.env = &env;
  ctx.protocol = &protocol;
  ctx.job = &job;
  ctx.run = run;
  ctx.specs = continuous_metric_specs(env, protocol);
  RunRecord record;
  record.run = run;
  record.action_names = env.action_names;
  record.metric_specs = ctx.specs;

  // The samples, unscaled: exactly what the simulator produced. A failing
  // simulator fails the run.
  kernels::RandomStream sample_stream = stream_for(job.seed, run, Purpose::samples);
  Walks walks;
  try {
    walks = random_walks(env, protocol, sample_stream);
  } catch (const EnvironmentError& error) {
    throw EnvironmentError("run " + std::to_string(run) + ": " + error.what());
  }
  const kernels::SampleBatch& batch = walks.batch;
  const Eigen::Index d = env.observation_dimension;
  record.samples.actions = batch.actions;
  record.samples.rewards = batch.rewards;
  record.samples.terminals = batch.terminals;
  record.samples.observations.resize(static_cast<Eigen::Index>(batch.size()), d);
  record.samples.next_observations.resize(static_cast<Eigen::Index>(batch.size()), d);
  for (std::size_t i = 0; i < batch.size(); ++i) {
    const auto row = static_cast<Eigen::Index>(i);
    record.samples.observations.row(row) = walks.observations.row(batch.states[i]);
    record.samples.next_observations.row(row) = walks.observations.row(batch.next_states[i]);
  }
  for (const NamedArray& array : env.run_arrays) record.arrays.push_back(array);
  if (!env.stop_flags_array.empty()) {
    record.arrays.push_back({env.stop_flags_array,
                             {static_cast<std::int64_t>(walks.stop_flags.size())},
                             walks.stop_flags,
                             ElementType::kUInt8});
  }
  if (env.store_scale) {
    record.arrays.push_back(
        {"observation_scale", {static_cast<std::int64_t>(protocol.scale.size())}, protocol.scale});
  }
  ctx.observations = scaled_observations(walks.observations, protocol.scale);

  // The SOM on every observation of the walks (paper: 24 x 29 units for 20,000 samples).
  kernels::SomOptions som_options = protocol.som;
  if (protocol.som_grid_from_samples) {
    const kernels::SomGrid grid = kernels::som_grid_for(ctx.observations);
    som_options.rows = grid.rows;
    som_options.cols = grid.cols;
  }
  kernels::RandomStream som_stream = stream_for(job.seed, run, Purpose::model);
  const kernels::SelfOrganizingMap som =
      kernels::train_self_organizing_map(ctx.observations, som_options, &som_stream);
  const auto& prototypes = som.prototypes();
  record.arrays.push_back(matrix_array("som/prototypes", prototypes));
  record.arrays.push_back(matrix_array("som/grid", som.grid_coordinates()));
  record.arrays.push_back({"som/quantization_error",
                           {static_cast<std::int64_t>(som.quantization_errors().size())},
                           som.quantization_errors()});
  ctx.som = &som;
  ctx.state_units = som.best_matching_units(ctx.observations);
  ctx.batch = job.lspi.fold_duplicates ? kernels::fold_duplicate_samples(batch) : batch;

  // The graph over units: BMU(s) -> BMU(s') per sample, weight = prototype distance.
  std::vector<kernels::NodeTransition> transitions(batch.size());
  std::vector<std::uint8_t> occupied(static_cast<std::size_t>(som.num_units()), 0);
  for (std::size_t i = 0; i < batch.size(); ++i) {
    const std::int32_t from = ctx.state_units.units[static_cast<std::size_t>(batch.states[i])];
    const std::int32_t to = ctx.state_units.units[static_cast<std::size_t>(batch.next_states[i])];
    transitions[i] = {from, to};
  }
  for (std::int32_t u : ctx.state_units.units) occupied[static_cast<std::size_t>(u)] = 1;
  ctx.occupied = occupied;
  record.graph = kernels::transition_graph(prototypes, transitions);
  record.node_states = prototypes;
  record.arrays.push_back({"graph/occupied",
                           {static_cast<std::int64_t>(occupied.size())},
                           std::vector<double>(occupied.begin(), occupied.end()),
                           ElementType::kUInt8});
  record.arrays.push_back(
      {"state_units",
       {static_cast<std::int64_t>(ctx.state_units.units.size())},
       std::vector<double>(ctx.state_units.units.begin(), ctx.state_units.units.end()),
       ElementType::kInt32});

  // Centres: the occupied units in a random order.
  std::vector<std::int32_t> centers;
  for (std::int32_t u = 0; u < som.num_units(); ++u) {
    if (occupied[static_cast<std::size_t>(u)]) centers.push_back(u);
  }
  kernels::RandomStream center_stream = stream_for(job.seed, run, Purpose::centers);
  kernels::shuffle(centers, center_stream);
  ctx.graph = run_graph(record.graph, occupied, std::move(centers), prototypes, points);
  ctx.eigenbases = run_eigenbases(record.graph, occupied, job.pvf, points);
  const bool pvf_shift = job.pvf.actions == kernels::BasisScheme::shift &&
                         !pvf_counts(points, ctx.graph.nodes).empty();
  if (job.basis.scheme == kernels::BasisScheme::shift || pvf_shift) {
    ctx.model = std::make_unique<kernels::EmpiricalTransitionModel>(
        static_cast<std::int32_t>(ctx.observations.rows()), env.num_actions, batch.states,
        batch.actions, batch.next_states);
  }

  record.fits = fit_points(ctx, points);
  return record;
}

std::vector<DatasetSpecs> continuous_dataset_specs(std::span<const DatasetSpecs> own) {
  static constexpr std::array kContinuousDatasets = {
      DatasetSpec{"observation_scale", "observation_dim", "task state units",
                  "the divisor of each observation dimension before the SOM and the kernels "
                  "([<task>.scale])"},
      DatasetSpec{"som/prototypes", "node,observation_dim", "scaled state units",
                  "the prototype of each SOM unit (observation / observation_scale)"},
      DatasetSpec{"som/grid", "node,grid_axis", "index",
                  "(row, column) of each unit on the SOM grid"},
      DatasetSpec{"som/quantization_error", "epoch", "scaled state units",
                  "mean distance to the BMU after each epoch"},
      DatasetSpec{"state_units", "state", "node id",
                  "the BMU of every observation of the walks, in series order"},
      DatasetSpec{"graph/occupied", "node", "flag",
                  "1 if an observation has the SOM unit as its BMU"},
      DatasetSpec{"fit:unit_policy", "node", "action code",
                  "greedy action at each SOM unit's prototype"},
      DatasetSpec{"fit:evaluation/returns", "episode", "reward", "the return of each test episode"},
      DatasetSpec{"fit:evaluation/trajectory_*", "step,state_field", "task state units",
                  "the simulator's state along the test episode, the start first "
                  "(sims/<task>/README.md)"},
  };
  std::vector<DatasetSpecs> specs(own.begin(), own.end());
  specs.push_back({"continuous tasks", kContinuousDatasets});
  specs.push_back(graph_dataset_specs());
  return specs;
}

}  // namespace ggk::engine
