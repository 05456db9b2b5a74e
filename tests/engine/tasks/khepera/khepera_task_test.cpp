// The Khepera task (engine/tasks/khepera/khepera_task.hpp): a tiny job run end
// to end, its fits and metrics, the graph diagnostics and the arena arrays
// recomputed from the run, bit-identical for 1 and 2 threads.

#include "engine/tasks/khepera/khepera_task.hpp"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <map>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include "engine/job/job_file.hpp"
#include "engine/run/job_runner.hpp"
#include "engine/tasks/khepera/khepera_test_job.hpp"
#include "engine/tasks/task_list.hpp"
#include "kernels/graph_diagnostics.hpp"
#include "kernels/shortest_paths.hpp"
#include "sims/khepera/khepera.hpp"
#include "support/job_text.hpp"
#include "support/results_compare.hpp"

namespace ggk::engine {
namespace {

namespace khepera = sims::khepera;
using namespace test_support;

const KheperaTaskConfig& khepera_task_config(const JobSpec& job) {
  return task_config_as<KheperaTaskConfig>(job);
}

std::vector<double> values_of(const Eigen::VectorXd& v) {
  return {v.data(), v.data() + v.size()};
}

RunRecord khepera_run_with_threads(const JobSpec& job, std::int32_t run, std::size_t threads) {
  const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
  return compute_run(job, run);
}

// The graph diagnostics (issue 11) recomputed from the stored run, and the
// arena arrays of Fig. 4(a) against the simulator.
TEST(KheperaJob, DiagnosticsAndArenaMatchTheStoredRun) {
  const JobSpec job = parse_job(std::string(kKheperaJob) + "[basis]\nscheme = \"copy\"\n",
                                "tiny.toml", task_tables(), no_output_check());
  const RunRecord record = compute_run(job, 0);
  const KheperaTaskConfig& config = khepera_task_config(job);
  const khepera::Khepera robot(config.simulator);

  std::vector<std::uint8_t> occupied(static_cast<std::size_t>(record.graph.num_nodes), 0);
  for (const NamedArray& a : record.arrays) {
    if (a.name != "graph/occupied") continue;
    for (std::size_t u = 0; u < a.values.size(); ++u) occupied[u] = a.values[u] != 0.0;
  }
  std::int64_t edges = 0;
  for (std::int32_t u = 0; u < record.graph.num_nodes; ++u) {
    for (std::int32_t v : record.graph.neighbors(u)) edges += u < v;
  }
  ASSERT_EQ(record.fits.size(), 2u);
  // The stretch is the graph's, between its first min(100, nodes) centres
  // whatever the job sweeps: those of a fit with that many kernels.
  JobSpec wide = job;
  const std::map<std::string, double> first(record.fits.front().metrics.begin(),
                                            record.fits.front().metrics.end());
  wide.sweep.kernels = {std::min(100, static_cast<std::int32_t>(first.at("graph_nodes")))};
  const std::vector<std::int32_t> first_centers = compute_run(wide, 0).fits.front().centers;
  ASSERT_EQ(first_centers.size(), static_cast<std::size_t>(wide.sweep.kernels.front()));
  const double stretch = kernels::geodesic_stretch(
      kernels::geodesic_distances(record.graph, first_centers), first_centers, record.node_states);
  for (const FitRecord& fit : record.fits) {
    const std::map<std::string, double> metrics(fit.metrics.begin(), fit.metrics.end());
    EXPECT_EQ(metrics.at("edges"), static_cast<double>(edges));
    EXPECT_EQ(metrics.at("median_degree"), kernels::median_degree(record.graph, occupied));
    EXPECT_EQ(metrics.at("geodesic_stretch"), stretch);
    EXPECT_GE(metrics.at("geodesic_stretch"), 1.0);
    EXPECT_GT(metrics.at("kernel_gap"), 0.0);
    EXPECT_LT(metrics.at("kernel_gap"), 1.0);
  }
  // GGK and OGK fits of one sweep point share centres and width: the same gap.
  EXPECT_EQ(record.fits[0].metrics.back(), record.fits[1].metrics.back());

  std::map<std::string, const NamedArray*> arrays;
  for (const NamedArray& a : record.arrays) arrays[a.name] = &a;
  const khepera::Pose start = robot.start_pose();
  EXPECT_EQ(arrays.at("arena/start")->values,
            (std::vector<double>{start.x, start.y, start.heading}));
  const khepera::Readings clean = robot.sense_noiseless(start);
  EXPECT_EQ(arrays.at("robot/start_readings")->values,
            std::vector<double>(clean.begin(), clean.end()));
  const NamedArray& rays = *arrays.at("robot/start_rays");
  ASSERT_EQ(rays.shape, (std::vector<std::int64_t>{24, 5}));
  for (std::int32_t i = 0; i < khepera::kNumSensors; ++i) {
    const khepera::SensorRays hit = robot.sensor_rays(start, i);
    const double distances[3] = {hit.left, hit.centre, hit.right};
    for (std::size_t k = 0; k < 3; ++k) {
      const double* ray = &rays.values[(3 * static_cast<std::size_t>(i) + k) * 5];
      const double length = std::hypot(ray[2] - ray[0], ray[3] - ray[1]);
      const bool seen = distances[k] <= config.simulator.sensors.range;
      EXPECT_EQ(ray[4], seen ? 1.0 : 0.0);
      EXPECT_NEAR(length, seen ? distances[k] : config.simulator.sensors.range, 1e-9);
    }
  }
}

TEST(KheperaJob, TinyRunFitsAndIsIdenticalForOneAndTwoThreads) {
  const JobSpec job = parse_job(std::string(kKheperaJob) + "[basis]\nscheme = \"copy\"\n",
                                "tiny.toml", task_tables(), no_output_check());
  const RunRecord one = khepera_run_with_threads(job, 0, 1);
  const RunRecord two = khepera_run_with_threads(job, 0, 2);

  ASSERT_EQ(one.fits.size(), 2u);  // ggk and ogk, 5 kernels
  EXPECT_EQ(one.samples.actions.size(), 500u);
  EXPECT_EQ(one.samples.observations.rows(), 500);
  EXPECT_EQ(one.samples.observations.cols(), khepera::kNumSensors);
  EXPECT_EQ(one.node_states.rows(), 20);  // the 4 x 5 SOM's prototypes
  for (const FitRecord& fit : one.fits) {
    SCOPED_TRACE(std::string(kernel_type_name(fit.point.basis)));
    EXPECT_TRUE(fit.status == "converged" || fit.status == "max_iterations")
        << fit.status << ": " << fit.message;
    const std::map<std::string, double> metrics(fit.metrics.begin(), fit.metrics.end());
    ASSERT_EQ(metrics.size(), khepera_metric_names().size());
    const double mean_return = metrics.at("mean_return");
    EXPECT_TRUE(std::isfinite(mean_return));
    // At most test_max_steps forward steps, at least one collision per episode.
    EXPECT_LE(mean_return, 150.0);
    EXPECT_GE(mean_return, -2.0);
    EXPECT_GE(metrics.at("mean_steps"), 1.0);
    EXPECT_LE(metrics.at("mean_steps"), 150.0);
    EXPECT_GE(metrics.at("lspi_iterations"), 1.0);
    EXPECT_GT(metrics.at("graph_nodes"), 5.0);
    EXPECT_LE(metrics.at("graph_nodes"), 20.0);
    EXPECT_EQ(fit.centers.size(), 5u);
    EXPECT_EQ(fit.lspi.weights.size(), 4 * 5);
  }

  // Bit-identical for 1 and 2 threads: samples, map, graph, every fit.
  EXPECT_EQ(one.samples.actions, two.samples.actions);
  EXPECT_TRUE(one.samples.observations == two.samples.observations);
  EXPECT_TRUE(one.node_states == two.node_states);
  EXPECT_EQ(one.graph.indices, two.graph.indices);
  EXPECT_TRUE(same_bits(one.graph.weights, two.graph.weights));
  ASSERT_EQ(one.arrays.size(), two.arrays.size());
  for (std::size_t i = 0; i < one.arrays.size(); ++i) {
    EXPECT_EQ(one.arrays[i].name, two.arrays[i].name);
    EXPECT_TRUE(same_bits(one.arrays[i].values, two.arrays[i].values)) << one.arrays[i].name;
  }
  ASSERT_EQ(one.fits.size(), two.fits.size());
  for (std::size_t i = 0; i < one.fits.size(); ++i) {
    const FitRecord& a = one.fits[i];
    const FitRecord& b = two.fits[i];
    EXPECT_EQ(a.status, b.status);
    EXPECT_EQ(a.centers, b.centers);
    EXPECT_TRUE(same_bits(values_of(a.lspi.weights), values_of(b.lspi.weights)));
    ASSERT_EQ(a.metrics.size(), b.metrics.size());
    for (std::size_t m = 0; m < a.metrics.size(); ++m) {
      EXPECT_EQ(a.metrics[m].first, b.metrics[m].first);
      EXPECT_TRUE(same_bits(std::vector<double>{a.metrics[m].second},
                            std::vector<double>{b.metrics[m].second}))
          << a.metrics[m].first;
    }
    ASSERT_EQ(a.arrays.size(), b.arrays.size());
    for (std::size_t k = 0; k < a.arrays.size(); ++k) {
      EXPECT_EQ(a.arrays[k].name, b.arrays[k].name);
      EXPECT_TRUE(same_bits(a.arrays[k].values, b.arrays[k].values)) << a.arrays[k].name;
    }
  }
}

}  // namespace
}  // namespace ggk::engine
