// [lspi] evaluate_iterations: every LSPI iteration's weights and the protocol's
// test of its greedy policy are stored per fit (history/weights,
// history/<tested metric>). Checked on the shipped CI job of every registered
// task (support/shipped_jobs.hpp: a new task is covered at once): the option
// changes no fit's own result, the last iterate is the fit's weights, and the
// test of the last iterate gives the fit's own metrics, bit for bit.

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "engine/job/job_file.hpp"
#include "engine/job/sweep.hpp"
#include "engine/tasks/task_list.hpp"
#include "support/shipped_jobs.hpp"

namespace ggk::engine {
namespace {

namespace fs = std::filesystem;

bool same_value(double a, double b) {
  return (std::isnan(a) && std::isnan(b)) || a == b;
}

const NamedArray* find_array(const FitRecord& fit, const std::string& name) {
  for (const NamedArray& array : fit.arrays) {
    if (array.name == name) return &array;
  }
  return nullptr;
}

class IterationTests : public ::testing::TestWithParam<std::string> {
 protected:
  void SetUp() override {
    if (std::getenv("GGK_SOURCE_DIR") == nullptr) {
      GTEST_SKIP() << "GGK_SOURCE_DIR is not set (run through ctest)";
    }
    const std::optional<fs::path> path = test_support::ci_job_for(GetParam());
    ASSERT_TRUE(path) << "no CI job (jobs/ci*.toml) runs task " << GetParam();
    JobLoadOptions options;
    options.check_output = false;
    options.overrides = {"runs=1"};
    job_ = load_job_file(*path, task_tables(), options);
  }
  RunRecord compute(bool evaluate_iterations) const {
    JobSpec job = job_;
    job.lspi.evaluate_iterations = evaluate_iterations;
    const std::vector<SweepPoint> points = expand_sweep(job);
    return find_task(job.task)->compute_run(job, 0, points);
  }
  JobSpec job_;
};

TEST_P(IterationTests, StoreEveryIterateAndItsTestWithoutChangingTheFit) {
  const RunRecord plain = compute(false);
  const RunRecord traced = compute(true);
  ASSERT_EQ(plain.fits.size(), traced.fits.size());
  ASSERT_FALSE(plain.fits.empty());
  for (std::size_t f = 0; f < plain.fits.size(); ++f) {
    const FitRecord& a = plain.fits[f];
    const FitRecord& b = traced.fits[f];
    SCOPED_TRACE("fit " + std::to_string(f));
    ASSERT_EQ(a.status, b.status);
    EXPECT_EQ(a.lspi.weights, b.lspi.weights);
    EXPECT_EQ(a.lspi.policy, b.lspi.policy);
    ASSERT_EQ(a.metrics.size(), b.metrics.size());
    for (std::size_t i = 0; i < a.metrics.size(); ++i) {
      EXPECT_EQ(a.metrics[i].first, b.metrics[i].first);
      EXPECT_TRUE(same_value(a.metrics[i].second, b.metrics[i].second)) << a.metrics[i].first;
    }
    EXPECT_EQ(find_array(a, "history/weights"), nullptr);
    if (b.lspi.weights.size() == 0) continue;

    const NamedArray* weights = find_array(b, "history/weights");
    ASSERT_NE(weights, nullptr);
    const auto iterations = static_cast<std::int64_t>(b.lspi.iterations());
    const auto k = static_cast<std::int64_t>(b.lspi.weights.size());
    ASSERT_EQ(weights->shape, (std::vector<std::int64_t>{iterations, k}));
    const std::vector<double> last(weights->values.end() - k, weights->values.end());
    EXPECT_EQ(last, std::vector<double>(b.lspi.weights.data(), b.lspi.weights.data() + k));
    // The weight changes recorded by LSPI are those of the stored iterates.
    for (std::int64_t it = 1; it < iterations; ++it) {
      double squares = 0.0;
      for (std::int64_t j = 0; j < k; ++j) {
        const double d = weights->values[static_cast<std::size_t>(it * k + j)] -
                         weights->values[static_cast<std::size_t>((it - 1) * k + j)];
        squares += d * d;
      }
      EXPECT_NEAR(b.lspi.history[static_cast<std::size_t>(it)].weight_change, std::sqrt(squares),
                  1e-9 * (1.0 + std::sqrt(squares)));
    }

    // The tested metrics (a task's test of a policy) have a history each, the
    // others (LSPI's, the graph's) none; each history ends at the fit's metric.
    EXPECT_EQ(find_array(b, "history/lspi_iterations"), nullptr);
    EXPECT_EQ(find_array(b, "history/kernel_gap"), nullptr);
    std::int32_t histories = 0;
    for (const auto& [name, value] : b.metrics) {
      const NamedArray* series = find_array(b, "history/" + name);
      if (series == nullptr) continue;
      ++histories;
      ASSERT_EQ(series->shape, std::vector<std::int64_t>{iterations}) << name;
      EXPECT_TRUE(same_value(series->values.back(), value)) << name;
    }
    EXPECT_GE(histories, 1) << "no metric of the task's test has a history";
  }
}

INSTANTIATE_TEST_SUITE_P(EveryTask, IterationTests,
                         ::testing::ValuesIn(test_support::registered_task_names()),
                         [](const ::testing::TestParamInfo<std::string>& param) {
                           return test_support::parameter_name(param.param);
                         });

}  // namespace
}  // namespace ggk::engine
