// The continuous protocol (engine/tasks/continuous_protocol.hpp) on a task of
// the tests' own (tests/support/line_walker.hpp): the samples stored unscaled,
// the SOM and the kernels in scaled units (a scale that changes nothing but the
// units changes no fit), the metrics in declared order, three bases, and the
// record bit for bit the same for 1 and 2 threads; the memory estimate covers
// the record.

#include "engine/tasks/continuous_protocol.hpp"

#include <map>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include "engine/job/sweep.hpp"
#include "engine/tasks/record_bytes.hpp"
#include "support/line_walker.hpp"
#include "support/results_compare.hpp"

namespace ggk::engine {
namespace {

using test_support::line_walker_environment;
using test_support::line_walker_protocol;
using test_support::same_bits;

JobSpec line_walker_job() {
  JobSpec job;
  job.name = "line";
  job.task = "line_walker";
  job.seed = 7;
  job.sweep.basis = {KernelType::ggk, KernelType::ogk, KernelType::pvf};
  job.sweep.kernels = {4};
  job.sweep.sigma = {0.3};
  job.sweep.solver = {kernels::LspiSolver::brm};
  job.sweep.lambda = {1e-6};
  job.basis.scheme = kernels::BasisScheme::copy;
  return job;
}

RunRecord run_with_threads(const ContinuousEnvironment& env, const ContinuousProtocol& protocol,
                           const JobSpec& job, std::size_t threads) {
  const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
  const std::vector<SweepPoint> points = expand_sweep(job);
  return run_continuous_protocol(env, protocol, job, 0, points);
}

const NamedArray& record_array(const RunRecord& record, const std::string& name) {
  for (const NamedArray& array : record.arrays) {
    if (array.name == name) return array;
  }
  throw std::runtime_error("no array " + name);
}

TEST(ContinuousProtocol, ThreeBasesUnscaledSamplesAndTheSameForOneAndTwoThreads) {
  const ContinuousEnvironment env = line_walker_environment();
  const ContinuousProtocol protocol = line_walker_protocol();
  const JobSpec job = line_walker_job();
  const RunRecord one = run_with_threads(env, protocol, job, 1);
  const RunRecord two = run_with_threads(env, protocol, job, 2);

  // The samples as the walker produced them: (x, 2 x), unscaled.
  ASSERT_GT(one.samples.observations.rows(), 0);
  for (Eigen::Index i = 0; i < one.samples.observations.rows(); ++i) {
    EXPECT_EQ(one.samples.observations(i, 1), 2.0 * one.samples.observations(i, 0));
  }
  EXPECT_EQ(one.action_names, env.action_names);
  EXPECT_EQ(record_array(one, "observation_scale").values, protocol.scale);
  EXPECT_EQ(record_array(one, "samples/bumps").values.size(), one.samples.actions.size());
  // The SOM sees x / 10 and 2 x / 20: its prototypes lie on the diagonal.
  for (Eigen::Index u = 0; u < one.node_states.rows(); ++u) {
    EXPECT_NEAR(one.node_states(u, 0), one.node_states(u, 1), 1e-9);
  }

  ASSERT_EQ(one.fits.size(), 3u);
  const std::vector<MetricSpec> specs = continuous_metric_specs(env, protocol);
  for (const FitRecord& fit : one.fits) {
    SCOPED_TRACE(std::string(kernel_type_name(fit.point.basis)));
    EXPECT_TRUE(fit.status == "converged" || fit.status == "max_iterations")
        << fit.status << ": " << fit.message;
    ASSERT_EQ(fit.metrics.size(), specs.size());
    for (std::size_t m = 0; m < specs.size(); ++m) EXPECT_EQ(fit.metrics[m].first, specs[m].name);
    const std::map<std::string, double> metrics(fit.metrics.begin(), fit.metrics.end());
    EXPECT_GE(metrics.at("success_rate"), 0.0);
    EXPECT_LE(metrics.at("success_rate"), 1.0);
    EXPECT_GE(metrics.at("mean_steps"), 1.0);
    EXPECT_LE(metrics.at("mean_steps"), protocol.test_max_steps);
    EXPECT_EQ(fit.lspi.weights.size(), 2 * 4);
  }

  // Bit-identical for 1 and 2 threads.
  EXPECT_TRUE(one.samples.observations == two.samples.observations);
  EXPECT_TRUE(one.node_states == two.node_states);
  ASSERT_EQ(one.arrays.size(), two.arrays.size());
  for (std::size_t i = 0; i < one.arrays.size(); ++i) {
    EXPECT_TRUE(same_bits(one.arrays[i].values, two.arrays[i].values)) << one.arrays[i].name;
  }
  for (std::size_t i = 0; i < one.fits.size(); ++i) {
    const Eigen::VectorXd& a = one.fits[i].lspi.weights;
    const Eigen::VectorXd& b = two.fits[i].lspi.weights;
    EXPECT_TRUE(same_bits(std::vector<double>(a.data(), a.data() + a.size()),
                          std::vector<double>(b.data(), b.data() + b.size())));
    ASSERT_EQ(one.fits[i].metrics.size(), two.fits[i].metrics.size());
    for (std::size_t m = 0; m < one.fits[i].metrics.size(); ++m) {
      EXPECT_TRUE(same_bits(std::vector<double>{one.fits[i].metrics[m].second},
                            std::vector<double>{two.fits[i].metrics[m].second}));
    }
  }
}

// Scaling every dimension and the width by the same power of two changes no
// rounding: the same fits bit for bit, so the scale reaches the SOM and every
// kernel and nothing else.
TEST(ContinuousProtocol, ScaleAndWidthTogetherChangeNoFit) {
  const ContinuousEnvironment env = line_walker_environment();
  ContinuousProtocol protocol = line_walker_protocol();
  JobSpec job = line_walker_job();
  job.sweep.basis = {KernelType::ggk, KernelType::ogk};
  const RunRecord base = run_with_threads(env, protocol, job, 1);
  for (double& s : protocol.scale) s *= 4.0;
  job.sweep.sigma = {0.3 / 4.0};
  const RunRecord scaled = run_with_threads(env, protocol, job, 1);
  for (std::size_t i = 0; i < base.fits.size(); ++i) {
    EXPECT_EQ(base.fits[i].lspi.policy, scaled.fits[i].lspi.policy);
    const std::map<std::string, double> a(base.fits[i].metrics.begin(), base.fits[i].metrics.end());
    const std::map<std::string, double> b(scaled.fits[i].metrics.begin(),
                                          scaled.fits[i].metrics.end());
    EXPECT_EQ(a.at("mean_return"), b.at("mean_return"));
    EXPECT_EQ(a.at("mean_steps"), b.at("mean_steps"));
  }
  // A different scale for one dimension is a different quantiser.
  protocol.scale = {10.0, 1.0};
  const RunRecord other = run_with_threads(env, protocol, line_walker_job(), 1);
  EXPECT_FALSE(other.node_states.isApprox(base.node_states));
}

TEST(ContinuousProtocol, MemoryEstimateCoversTheRecord) {
  const ContinuousEnvironment env = line_walker_environment();
  const ContinuousProtocol protocol = line_walker_protocol();
  const JobSpec job = line_walker_job();
  ContinuousSizes sizes;
  sizes.observation_dimension = 2.0;
  sizes.actions = 2.0;
  sizes.trace_dimension = 1.0;
  sizes.stop_flags = 1.0;
  const RunMemoryEstimate estimate = estimate_continuous_run(sizes, protocol, job);
  const double held = record_bytes(run_with_threads(env, protocol, job, 1));
  EXPECT_GE(estimate.record_bytes, held);
  EXPECT_LT(estimate.record_bytes, 10.0 * held);
}

}  // namespace
}  // namespace ggk::engine
