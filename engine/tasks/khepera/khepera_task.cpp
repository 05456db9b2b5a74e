#include "engine/tasks/khepera/khepera_task.hpp"

#include "engine/tasks/khepera/khepera_table.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <numeric>
#include <utility>
#include <variant>

#include <tbb/parallel_for.h>

#include "engine/tasks/seeds.hpp"
#include "kernels/gaussian_kernels.hpp"
#include "kernels/graph_diagnostics.hpp"
#include "kernels/lspi.hpp"
#include "kernels/shortest_paths.hpp"
#include "kernels/state_action_basis.hpp"
#include "kernels/transition_model.hpp"
#include "sims/khepera/khepera.hpp"

namespace ggk::engine {

namespace {

namespace khepera = sims::khepera;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// The random walks. States are the readings in series order: reading t of series
// k is state k * (steps + 1) + t; sample (k, t) goes from state (k, t) to (k, t + 1).
struct Walks {
  kernels::RowMatrixXd readings;  // states x 8
  kernels::SampleBatch batch;
  std::vector<double> collisions;  // per sample, 1 if the step was undone
};

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

// The kernel gap's sum over the readings per centre (in centre order) for one width.
struct SharedGap {
  double sigma = 0.0;
  std::vector<double> per_center;
};

// Everything the fits of a run share.
struct RunContext {
  const khepera::Khepera* robot;
  const JobSpec* job;
  std::int32_t run;
  const Walks* walks;
  const kernels::SelfOrganizingMap* som;
  kernels::BestMatches state_units;       // best-matching unit of every state
  std::vector<std::int32_t> centers;      // centre order over occupied units
  kernels::RowMatrixXd center_distances;  // shortest paths from the first centres
  std::int32_t graph_nodes = 0;           // occupied units
  std::vector<std::uint8_t> occupied;     // per unit: the best match of some sample
  kernels::SampleBatch batch;             // the walks' samples, folded if the job asks
  std::unique_ptr<kernels::EmpiricalTransitionModel> model;  // for the shift scheme
  // The run's graph diagnostics (kernels/graph_diagnostics.hpp).
  double edges = 0.0;
  double median_degree = 0.0;
  double geodesic_stretch = 0.0;
  // The kernel gap's per-centre sums, per width (formed before the fits start).
  std::vector<SharedGap> kernel_gaps;
};

// kernel_gap of a fit: the mean over the walks' readings and the fit's centres of
// |K_GGK - K_OGK| at the fit's width (untruncated), GGK in the continuous form
// the fit's kernel table uses.
// The kernel gap's sum over the readings for each of `centers` (one term per centre).
std::vector<double> kernel_gap_terms(const RunContext& ctx, std::span<const std::int32_t> centers,
                                     double sigma) {
  const kernels::RowMatrixXd& readings = ctx.walks->readings;
  const auto n = static_cast<std::size_t>(readings.rows());
  std::vector<double> terms(centers.size());
  tbb::parallel_for(std::size_t{0}, centers.size(), [&](std::size_t j) {
    std::vector<double> geodesic(n), euclidean(n);
    const auto center = ctx.som->prototypes().row(centers[j]);
    for (std::size_t i = 0; i < n; ++i) {
      const auto row = static_cast<Eigen::Index>(i);
      geodesic[i] = ctx.state_units.distances[i] +
                    ctx.center_distances(static_cast<Eigen::Index>(j), ctx.state_units.units[i]);
      euclidean[i] = (readings.row(row) - center).norm();
    }
    terms[j] = kernels::kernel_gap_sum(geodesic, euclidean, sigma);
  });
  return terms;
}

// The mean of the first p terms over the readings (summed in centre order).
double fit_kernel_gap(const RunContext& ctx, std::int32_t p, double sigma) {
  const SharedGap* gap = nullptr;
  for (const SharedGap& g : ctx.kernel_gaps) {
    if (g.sigma == sigma) gap = &g;
  }
  double sum = 0.0;
  for (std::int32_t j = 0; j < p; ++j) sum += gap->per_center[static_cast<std::size_t>(j)];
  const double pairs = static_cast<double>(ctx.walks->readings.rows()) * static_cast<double>(p);
  return pairs > 0.0 ? sum / pairs : kNaN;
}

// The state kernels of every reading of the walks for the first p centres.
kernels::SparseRowMatrix state_kernel_table(const RunContext& ctx, KernelType basis, double sigma,
                                            std::int32_t p) {
  const double truncation = ctx.job->basis.truncation;
  if (basis == KernelType::ggk) {
    return kernels::continuous_geodesic_gaussian_kernels(
        ctx.state_units.units, ctx.state_units.distances, ctx.center_distances.topRows(p), sigma,
        truncation);
  }
  kernels::RowMatrixXd center_vectors(p, khepera::kNumSensors);
  for (std::int32_t j = 0; j < p; ++j) {
    center_vectors.row(j) = ctx.som->prototypes().row(ctx.centers[static_cast<std::size_t>(j)]);
  }
  return kernels::ordinary_gaussian_kernels(ctx.walks->readings, center_vectors, sigma, truncation);
}

// K(s, c_j) of a fit for one reading, with the same arithmetic as the batch
// kernel functions (so a state's features equal its row of the table).
class ReadingKernels {
 public:
  ReadingKernels(const RunContext& ctx, const SweepPoint& point,
                 std::span<const std::int32_t> centers)
      : ctx_(ctx), point_(point), centers_(centers) {}

  Eigen::VectorXd operator()(std::span<const double> reading) const {
    const auto p = static_cast<Eigen::Index>(centers_.size());
    Eigen::VectorXd k(p);
    const double truncation = ctx_.job->basis.truncation;
    if (point_.basis == KernelType::ggk) {
      const kernels::BestMatch bmu = nearest_graph_node(reading);
      for (Eigen::Index j = 0; j < p; ++j) {
        k(j) = kernels::gaussian(bmu.distance + ctx_.center_distances(j, bmu.unit), point_.sigma);
      }
    } else {
      const Eigen::Map<const Eigen::RowVectorXd> x(reading.data(),
                                                   static_cast<Eigen::Index>(reading.size()));
      for (Eigen::Index j = 0; j < p; ++j) {
        k(j) = kernels::gaussian(
            (x - ctx_.som->prototypes().row(centers_[static_cast<std::size_t>(j)])).norm(),
            point_.sigma);
      }
    }
    for (Eigen::Index j = 0; j < p; ++j) {
      if (!(k(j) > 0.0 && k(j) >= truncation)) k(j) = 0.0;
    }
    return k;
  }

 private:
  // n(s) of the continuous GGK: the nearest unit that is a node of the sample
  // graph. A unit no sample maps to is isolated (every shortest path from a centre
  // to it is infinite), so a reading whose best match is such a unit falls back to
  // the nearest occupied unit instead of getting all-zero features. For the
  // samples' own readings this is their best match.
  kernels::BestMatch nearest_graph_node(std::span<const double> reading) const {
    const kernels::BestMatch bmu = ctx_.som->best_matching_unit(reading);
    if (ctx_.occupied[static_cast<std::size_t>(bmu.unit)]) return bmu;
    const Eigen::Map<const Eigen::RowVectorXd> x(reading.data(),
                                                 static_cast<Eigen::Index>(reading.size()));
    kernels::BestMatch best{-1, std::numeric_limits<double>::infinity()};
    for (std::int32_t u = 0; u < ctx_.som->num_units(); ++u) {
      if (!ctx_.occupied[static_cast<std::size_t>(u)]) continue;
      const double d = (x - ctx_.som->prototypes().row(u)).norm();
      if (d < best.distance) best = {u, d};
    }
    return best;
  }

  const RunContext& ctx_;
  const SweepPoint& point_;
  std::span<const std::int32_t> centers_;
};

// Greedy action for kernel values k under the copy scheme: argmax_a w_a . k, ties
// to the lowest action (as kernels::greedy_policy).
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

// The protocol's test of greedy weights: test_episodes episodes from the start
// pose, from a fresh copy of the fit's evaluation stream (so the test of the last
// iterate is the fit's own test). A reading off the sample set is featurised with
// the copy scheme (no transition model exists for it).
struct EpisodeTest {
  double mean_return = 0.0;
  double collision_fraction = 0.0;
  double mean_steps = 0.0;
  std::vector<double> returns;
  std::vector<NamedArray> trajectories;  // evaluation/trajectory_<episode>, when asked
};

EpisodeTest test_episodes(const RunContext& ctx, const SweepPoint& point,
                          const ReadingKernels& kernels_of, const Eigen::VectorXd& weights,
                          bool keep_trajectories) {
  const khepera::Khepera& robot = *ctx.robot;
  const std::int32_t m = robot.num_actions();
  kernels::RandomStream random = stream_for(ctx.job->seed, ctx.run, Purpose::evaluation,
                                            static_cast<std::uint32_t>(point.evaluation_stream));
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

// state_kernels: the point's table (state_kernel_table), read only when the point
// is valid (no more kernels than graph nodes).
FitRecord fit_point(const RunContext& ctx, const SweepPoint& point,
                    const kernels::SparseRowMatrix& state_kernels) {
  const auto started = std::chrono::steady_clock::now();
  const khepera::Khepera& robot = *ctx.robot;
  const std::int32_t m = robot.num_actions();
  FitRecord fit;
  fit.point = point;
  const auto& names = khepera_metric_names();
  double kernel_gap = kNaN;
  auto set_metrics = [&](double mean_return, double collision_fraction, double mean_steps) {
    fit.metrics = {{names[0], mean_return},
                   {names[1], collision_fraction},
                   {names[2], mean_steps},
                   {names[3], static_cast<double>(fit.lspi.iterations())},
                   {names[4], static_cast<double>(ctx.graph_nodes)},
                   {names[5], ctx.edges},
                   {names[6], ctx.median_degree},
                   {names[7], ctx.geodesic_stretch},
                   {names[8], kernel_gap}};
  };
  if (point.kernels > ctx.graph_nodes) {
    fit.status = "invalid";
    fit.message = "run " + std::to_string(ctx.run) + ": " + std::to_string(point.kernels) +
                  " kernels requested but only " + std::to_string(ctx.graph_nodes) +
                  " SOM units hold samples";
    set_metrics(kNaN, kNaN, kNaN);
    return fit;
  }
  fit.centers.assign(ctx.centers.begin(), ctx.centers.begin() + point.kernels);
  kernel_gap = fit_kernel_gap(ctx, point.kernels, point.sigma);

  // The copy scheme's table is never formed: fit_lspi_copy_basis reads the state
  // kernels (the same result bit for bit).
  fit.lspi = ctx.job->basis.scheme == kernels::BasisScheme::shift
                 ? kernels::fit_lspi(kernels::shift_basis(state_kernels, m, *ctx.model), m,
                                     ctx.batch, lspi_options(point))
                 : kernels::fit_lspi_copy_basis(state_kernels, m, ctx.batch, lspi_options(point));
  fit.status = kernels::to_string(fit.lspi.status);
  fit.message = fit.lspi.message;
  if (fit.lspi.weights.size() == 0) {
    set_metrics(kNaN, kNaN, kNaN);
    return fit;
  }

  const ReadingKernels kernels_of(ctx, point, fit.centers);
  EpisodeTest test = test_episodes(ctx, point, kernels_of, fit.lspi.weights, true);
  set_metrics(test.mean_return, test.collision_fraction, test.mean_steps);
  for (NamedArray& trajectory : test.trajectories) fit.arrays.push_back(std::move(trajectory));
  fit.arrays.push_back(
      {"evaluation/returns", {static_cast<std::int64_t>(test.returns.size())}, test.returns});
  if (!fit.lspi.iterates.empty()) {
    // [lspi] evaluate_iterations: every iteration's weights and its greedy
    // policy's test under the fit's metric names; the last entries equal the fit's.
    const auto iterations = static_cast<std::int64_t>(fit.lspi.iterates.size());
    NamedArray weights{"history/weights", {iterations, fit.lspi.iterates.front().size()}, {}};
    std::vector<double> returns, collisions, steps;
    for (const Eigen::VectorXd& w : fit.lspi.iterates) {
      weights.values.insert(weights.values.end(), w.data(), w.data() + w.size());
      const EpisodeTest t = test_episodes(ctx, point, kernels_of, w, false);
      returns.push_back(t.mean_return);
      collisions.push_back(t.collision_fraction);
      steps.push_back(t.mean_steps);
    }
    fit.arrays.push_back(std::move(weights));
    fit.arrays.push_back({"history/" + names[0], {iterations}, std::move(returns)});
    fit.arrays.push_back({"history/" + names[1], {iterations}, std::move(collisions)});
    fit.arrays.push_back({"history/" + names[2], {iterations}, std::move(steps)});
  }

  // Fig. 5: the greedy action at every SOM unit's prototype.
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
// the solver: they share one state-kernel table (built once, freed when they
// are done, so no more tables are alive than before). The kernel gap's
// per-centre sums are formed first, once per width, for the largest valid count.
std::vector<FitRecord> fit_points(RunContext& ctx, std::span<const SweepPoint> points) {
  for (const SweepPoint& point : points) {
    if (point.kernels > ctx.graph_nodes) continue;
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
        ctx, std::span<const std::int32_t>(ctx.centers).first(g.per_center.size()), g.sigma);
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
  std::vector<FitRecord> fits(points.size());
  tbb::parallel_for(std::size_t{0}, groups.size(), [&](std::size_t g) {
    const std::vector<std::size_t>& group = groups[g];
    const SweepPoint& first = points[group.front()];
    const kernels::SparseRowMatrix table =
        first.kernels > ctx.graph_nodes
            ? kernels::SparseRowMatrix()
            : state_kernel_table(ctx, first.basis, first.sigma, first.kernels);
    tbb::parallel_for(std::size_t{0}, group.size(), [&](std::size_t f) {
      fits[group[f]] = fit_point(ctx, points[group[f]], table);
    });
  });
  return fits;
}

// The arena, the robot and its sensors' rays at the start pose, for Fig. 4(a)
// (results/plot_khepera_arena.py): arena/box [min x, min y, max x, max y,
// walled], arena/segments [n, 4] (a, b), arena/rectangles [n, 4] (min, max),
// arena/rotated_rectangles [n, 5] (centre, width, height, angle_deg),
// arena/discs [n, 3] (centre, radius), arena/start [x, y, heading (rad)],
// robot/radius, robot/sensors [8, 3] (x, y, heading_deg in the robot frame),
// robot/start_rays [24, 5] (row 3 i + k: sensor i's left, centre, right ray for
// k = 0, 1, 2: origin, end (the hit, or the range's end), 1 if it hit within
// range; the store keeps 1-D and 2-D arrays) and
// robot/start_readings [8] (noiseless).
std::vector<NamedArray> arena_arrays(const khepera::Khepera& robot) {
  const auto& c = robot.config();
  const khepera::Arena& arena = c.arena;
  NamedArray box{"arena/box",
                 {5},
                 {arena.min.x, arena.min.y, arena.max.x, arena.max.y, arena.walled ? 1.0 : 0.0}};
  NamedArray segments{"arena/segments", {0, 4}, {}}, rectangles{"arena/rectangles", {0, 4}, {}};
  NamedArray rotated{"arena/rotated_rectangles", {0, 5}, {}}, discs{"arena/discs", {0, 3}, {}};
  for (const khepera::Shape& shape : arena.obstacles) {
    if (const auto* g = std::get_if<khepera::Segment>(&shape)) {
      segments.values.insert(segments.values.end(), {g->a.x, g->a.y, g->b.x, g->b.y});
    } else if (const auto* r = std::get_if<khepera::Rectangle>(&shape)) {
      rectangles.values.insert(rectangles.values.end(), {r->min.x, r->min.y, r->max.x, r->max.y});
    } else if (const auto* q = std::get_if<khepera::RotatedRectangle>(&shape)) {
      rotated.values.insert(rotated.values.end(),
                            {q->center.x, q->center.y, q->width, q->height, q->angle_deg});
    } else if (const auto* d = std::get_if<khepera::Disc>(&shape)) {
      discs.values.insert(discs.values.end(), {d->center.x, d->center.y, d->radius});
    }
  }
  segments.shape[0] = static_cast<std::int64_t>(segments.values.size() / 4);
  rectangles.shape[0] = static_cast<std::int64_t>(rectangles.values.size() / 4);
  rotated.shape[0] = static_cast<std::int64_t>(rotated.values.size() / 5);
  discs.shape[0] = static_cast<std::int64_t>(discs.values.size() / 3);
  const khepera::Pose start = robot.start_pose();
  NamedArray start_pose{"arena/start", {3}, {start.x, start.y, start.heading}};
  NamedArray radius{"robot/radius", {1}, {c.body.radius}};
  NamedArray sensors{"robot/sensors", {khepera::kNumSensors, 3}, {}};
  NamedArray rays{"robot/start_rays", {3 * khepera::kNumSensors, 5}, {}};
  const double range = c.sensors.range;
  const double side = khepera::degrees_to_radians(c.sensors.side_ray_deg);
  const double ch = std::cos(start.heading), sh = std::sin(start.heading);
  for (std::int32_t i = 0; i < khepera::kNumSensors; ++i) {
    const khepera::IrSensor& mount = c.body.sensors[static_cast<std::size_t>(i)];
    sensors.values.insert(sensors.values.end(), {mount.x, mount.y, mount.heading_deg});
    const double ox = start.x + ch * mount.x - sh * mount.y;
    const double oy = start.y + sh * mount.x + ch * mount.y;
    const khepera::SensorRays hit = robot.sensor_rays(start, i);
    const double heading = start.heading + khepera::degrees_to_radians(mount.heading_deg);
    const std::array<std::pair<double, double>, 3> fan = {
        {{heading + side, hit.left}, {heading, hit.centre}, {heading - side, hit.right}}};
    for (const auto& [angle, distance] : fan) {
      const bool seen = distance <= range;
      const double length = seen ? distance : range;
      rays.values.insert(rays.values.end(), {ox, oy, ox + length * std::cos(angle),
                                             oy + length * std::sin(angle), seen ? 1.0 : 0.0});
    }
  }
  const khepera::Readings clean = robot.sense_noiseless(start);
  NamedArray readings{"robot/start_readings",
                      {khepera::kNumSensors},
                      std::vector<double>(clean.begin(), clean.end())};
  return {std::move(box),   std::move(segments),   std::move(rectangles), std::move(rotated),
          std::move(discs), std::move(start_pose), std::move(radius),     std::move(sensors),
          std::move(rays),  std::move(readings)};
}

}  // namespace

RunRecord run_khepera(const KheperaTaskConfig& config, const JobSpec& job, std::int32_t run,
                      std::span<const SweepPoint> points) {
  const khepera::Khepera robot(config.simulator);
  RunRecord record;
  record.run = run;

  kernels::RandomStream sample_stream = stream_for(job.seed, run, Purpose::samples);
  const Walks walks = random_walks(robot, sample_stream);
  const kernels::SampleBatch& batch = walks.batch;
  record.samples.actions = batch.actions;
  record.samples.rewards = batch.rewards;
  record.samples.terminals = batch.terminals;
  record.samples.observations.resize(static_cast<Eigen::Index>(batch.size()), khepera::kNumSensors);
  record.samples.next_observations.resize(static_cast<Eigen::Index>(batch.size()),
                                          khepera::kNumSensors);
  for (std::size_t i = 0; i < batch.size(); ++i) {
    const auto row = static_cast<Eigen::Index>(i);
    record.samples.observations.row(row) = walks.readings.row(batch.states[i]);
    record.samples.next_observations.row(row) = walks.readings.row(batch.next_states[i]);
  }
  for (NamedArray& array : arena_arrays(robot)) record.arrays.push_back(std::move(array));
  record.arrays.push_back({"samples/collisions",
                           {static_cast<std::int64_t>(walks.collisions.size())},
                           walks.collisions,
                           ElementType::kUInt8});

  // The SOM on every reading of the walks (paper: 24 x 29 units for 20,000 samples).
  kernels::SomOptions som_options = config.som;
  if (config.som_grid_from_samples) {
    const kernels::SomGrid grid = kernels::som_grid_for(walks.readings);
    som_options.rows = grid.rows;
    som_options.cols = grid.cols;
  }
  kernels::RandomStream som_stream = stream_for(job.seed, run, Purpose::model);
  const kernels::SelfOrganizingMap som =
      kernels::train_self_organizing_map(walks.readings, som_options, &som_stream);
  const auto& prototypes = som.prototypes();
  record.arrays.push_back(
      {"som/prototypes",
       {prototypes.rows(), prototypes.cols()},
       std::vector<double>(prototypes.data(), prototypes.data() + prototypes.size())});
  const kernels::RowMatrixXd grid = som.grid_coordinates();
  record.arrays.push_back({"som/grid",
                           {grid.rows(), grid.cols()},
                           std::vector<double>(grid.data(), grid.data() + grid.size())});
  record.arrays.push_back({"som/quantization_error",
                           {static_cast<std::int64_t>(som.quantization_errors().size())},
                           som.quantization_errors()});

  RunContext ctx;
  ctx.robot = &robot;
  ctx.job = &job;
  ctx.run = run;
  ctx.walks = &walks;
  ctx.som = &som;
  ctx.state_units = som.best_matching_units(walks.readings);
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
  for (std::int32_t u = 0; u < som.num_units(); ++u) {
    if (occupied[static_cast<std::size_t>(u)]) ctx.centers.push_back(u);
  }
  ctx.graph_nodes = static_cast<std::int32_t>(ctx.centers.size());
  kernels::RandomStream center_stream = stream_for(job.seed, run, Purpose::centers);
  kernels::shuffle(ctx.centers, center_stream);
  std::int32_t max_kernels = 0;
  for (const SweepPoint& p : points) max_kernels = std::max(max_kernels, p.kernels);
  const auto sources = std::span<const std::int32_t>(ctx.centers)
                           .first(static_cast<std::size_t>(std::min(max_kernels, ctx.graph_nodes)));
  ctx.center_distances = kernels::geodesic_distances(record.graph, sources);
  ctx.edges = static_cast<double>(kernels::undirected_edge_count(record.graph));
  ctx.median_degree = kernels::median_degree(record.graph, occupied);
  ctx.geodesic_stretch = kernels::geodesic_stretch(ctx.center_distances, sources, prototypes);
  if (job.basis.scheme == kernels::BasisScheme::shift) {
    ctx.model = std::make_unique<kernels::EmpiricalTransitionModel>(
        static_cast<std::int32_t>(walks.readings.rows()), robot.num_actions(), batch.states,
        batch.actions, batch.next_states);
  }

  record.fits = fit_points(ctx, points);
  return record;
}

RunMemoryEstimate estimate_khepera_run(const KheperaTaskConfig& config, const JobSpec& job) {
  const auto& c = config.simulator;
  const double d = khepera::kNumSensors, m = khepera::kNumActions;
  const double n = static_cast<double>(c.series) * c.steps_per_series;  // samples
  const double readings = static_cast<double>(c.series) * (c.steps_per_series + 1.0);
  kernels::SomGrid grid{config.som.rows, config.som.cols};
  if (config.som_grid_from_samples)
    grid = kernels::som_grid_for(static_cast<std::int64_t>(readings));
  const double units = static_cast<double>(grid.rows) * grid.cols;
  const std::vector<SweepPoint> points = expand_sweep(job);
  double max_kernels = 0.0;
  for (const SweepPoint& p : points) max_kernels = std::max<double>(max_kernels, p.kernels);
  max_kernels = std::min(max_kernels, units);  // a fit with more kernels than units never starts
  const bool shift = job.basis.scheme == kernels::BasisScheme::shift;

  RunMemoryEstimate estimate;
  // Readings (d doubles each) with their best-matching units (and as doubles in
  // the record); samples: the walks' batch and collision flags (grown by
  // doubling), their copy in the record (observations as readings), the LSPI
  // batch (every reading is its own state: folding keeps every sample) and the
  // graph's transition list; then first the folding's hash map or the graph's
  // edge lists; the shift scheme's transition model over the readings.
  const double record_samples = n * (2.0 * d * 8.0 + 13.0 + 8.0);
  estimate.add(
      count_text(n) + " samples per run (series x steps_per_series)",
      readings * (d * 8.0 + 12.0 + 8.0) + sample_batch_bytes(n) + 16.0 * n + record_samples +
          sample_batch_bytes(n) + 8.0 * n +
          std::max(job.lspi.fold_duplicates ? folding_bytes(n, n) : 0.0, graph_building_bytes(n)) +
          (shift ? readings * m * 8.0 + 20.0 * n : 0.0));
  // The SOM: training (prototypes, their dimension-major copy, the per-unit sums
  // and two smoothing passes over them: 43 doubles a unit) bounds what the map
  // keeps afterwards (prototypes twice, in the record, as graph nodes, grid).
  // Plus the unit graph.
  estimate.add("a " + count_text(grid.rows) + " x " + count_text(grid.cols) + " SOM (" +
                   count_text(units) + " units)",
               units * 43.0 * 8.0 + graph_bytes(n, units));
  estimate.add("the geodesic distances from " + count_text(max_kernels) + " centres to " +
                   count_text(units) + " units",
               max_kernels * units * 8.0);
  // The kernel gap's two distance rows (a double per reading each) per centre in
  // flight while its per-centre sums are formed (two: one per thread of -j 2).
  estimate.add("the kernel gap's distance rows (" + count_text(readings) + " readings)",
               2.0 * readings * 16.0);
  // A fit's state kernels, shared with the fits of the other solvers at the
  // same basis, width and kernel count; the shift scheme forms its m-row
  // feature table from them.
  estimate.add_per_fit(
      shift ? "the kernel and feature tables of a fit with " + count_text(max_kernels) +
                  " kernels (" + count_text(readings) + " readings x " + count_text(m) + " actions)"
            : "the state kernels of a fit with " + count_text(max_kernels) + " kernels (" +
                  count_text(readings) + " readings; the copy scheme forms no feature table)",
      shift ? kernel_and_feature_bytes(readings, max_kernels, m)
            : kernel_table_bytes(readings, max_kernels));
  estimate.add_per_fit("the LSPI system of a fit with " + count_text(m) + " x " +
                           count_text(max_kernels) + " basis functions",
                       lspi_bytes(readings, max_kernels, m, n));
  // The fits' results: LSPI systems, policies, the greedy action per unit, and
  // the episodes' trajectories (up to test_max_steps + 1 poses of 3 doubles,
  // grown by doubling).
  const double episodes = static_cast<double>(c.test_episodes) * (c.test_max_steps + 1.0) * 48.0;
  double fits = 0.0;
  for (const SweepPoint& p : points) {
    fits += fit_record_bytes(readings, std::min<double>(p.kernels, units), m,
                             p.solver == kernels::LspiSolver::brm) +
            episodes + units * 8.0;
  }
  estimate.add("the results of " + count_text(static_cast<double>(points.size())) + " fits", fits);
  // The arena's arrays for Fig. 4(a): 5 doubles an obstacle at most, and the
  // robot's 8 sensors (3 numbers, 3 rays of 5, a reading).
  const double arena =
      (static_cast<double>(c.arena.obstacles.size()) * 5.0 + 8.0 * 19.0 + 9.0) * 8.0;
  estimate.record_bytes = record_samples + readings * 8.0 + units * (80.0 + 64.0 + 8.0) +
                          graph_bytes(n, units) + fits + arena;
  return estimate;
}

TaskDefinition khepera_task_definition() {
  return {{"khepera",
           [](const TomlTableReader& job, const std::filesystem::path& job_dir,
              std::vector<JobInput>& inputs) -> std::any {
             return parse_khepera_table(job, job_dir, inputs);
           }},
          [](const JobSpec& job, std::int32_t run, std::span<const SweepPoint> points) {
            return run_khepera(task_config_as<KheperaTaskConfig>(job), job, run, points);
          },
          [](const JobSpec& job) {
            return estimate_khepera_run(task_config_as<KheperaTaskConfig>(job), job);
          },
          khepera_metric_kind};
}

}  // namespace ggk::engine
