// The registered tasks (engine/tasks/task_list.hpp): each one complete, and the
// metrics they declare (kind, unit, meaning, range; tasks/metric_spec.hpp).

#include "engine/tasks/task_list.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "engine/job/job_error.hpp"
#include "engine/job/job_file.hpp"
#include "engine/run/job_runner.hpp"
#include "engine/tasks/continuous_protocol.hpp"
#include "engine/tasks/discrete_protocol.hpp"
#include "engine/tasks/record_bytes.hpp"

namespace ggk::engine {
namespace {

namespace fs = std::filesystem;

TEST(MemoryCheck, EveryTaskEstimatesItsRuns) {
  for (const TaskDefinition& task : registered_tasks()) {
    EXPECT_NE(task.estimate_run_bytes, nullptr) << task.table.name;
  }
}

// Every registered task ships a job in jobs/, and every task's parser hands its
// distances to check_kernel_widths: a width at which every kernel value would
// be 0, or 1, is refused at [sweep] sigma in each task's shipped jobs.
TEST(KernelWidths, EveryTaskRefusesWidthsItsDistancesCannotUse) {
  const char* source_dir = std::getenv("GGK_SOURCE_DIR");
  if (source_dir == nullptr) GTEST_SKIP() << "GGK_SOURCE_DIR is not set (run through ctest)";
  std::set<std::string> shipped;
  for (const auto& entry : std::filesystem::directory_iterator(fs::path(source_dir) / "jobs")) {
    if (entry.path().extension() != ".toml") continue;
    JobLoadOptions options;
    options.check_output = false;
    std::string task;
    try {
      task = load_job_file(entry.path(), task_tables(), options).task;
    } catch (const JobError&) {
      continue;  // a study: `ggk run` reads it as one (job/study.hpp)
    }
    if (!shipped.insert(task).second) continue;
    for (const std::string sigma : {"1e-300", "1e300"}) {
      options.overrides = {"sweep.sigma=[" + sigma + "]"};
      try {
        load_job_file(entry.path(), task_tables(), options);
        ADD_FAILURE() << entry.path() << " accepts sigma = " << sigma;
      } catch (const JobError& error) {
        EXPECT_NE(std::string(error.what()).find("sigma"), std::string::npos) << error.what();
      }
    }
  }
  for (const TaskDefinition& task : registered_tasks()) {
    EXPECT_EQ(shipped.count(std::string(task.table.name)), 1u)
        << "no job in jobs/ runs task " << task.table.name;
  }
}

// One run of each task's first shipped CI job (jobs/ci*.toml, in name order),
// computed once for the tests below.
struct CiRun {
  fs::path path;
  JobSpec job;
  RunRecord record;
};

const std::vector<CiRun>& ci_runs(const char* source_dir) {
  static const std::vector<CiRun> runs = [source_dir] {
    std::vector<fs::path> jobs;
    for (const auto& entry : fs::directory_iterator(fs::path(source_dir) / "jobs")) {
      if (entry.path().filename().string().starts_with("ci")) jobs.push_back(entry.path());
    }
    std::sort(jobs.begin(), jobs.end());
    std::set<std::string> tasks;
    std::vector<CiRun> result;
    for (const fs::path& path : jobs) {
      JobLoadOptions options;
      options.check_output = false;
      JobSpec job;
      try {
        job = load_job_file(path, task_tables(), options);
      } catch (const JobError&) {
        continue;  // a study
      }
      if (!tasks.insert(job.task).second) continue;
      RunRecord record = compute_run(job, 0);
      result.push_back({path, std::move(job), std::move(record)});
    }
    return result;
  }();
  return runs;
}

// Every registered task's estimate covers what one run of its shipped CI job
// (jobs/ci*.toml) holds in its record, so a new task cannot ship an estimate
// that the runner's memory check would trust below the truth.
TEST(MemoryCheck, EveryTasksEstimateCoversItsCiRecord) {
  const char* source_dir = std::getenv("GGK_SOURCE_DIR");
  if (source_dir == nullptr) GTEST_SKIP() << "GGK_SOURCE_DIR is not set (run through ctest)";
  std::set<std::string> checked;
  for (const CiRun& run : ci_runs(source_dir)) {
    checked.insert(run.job.task);
    SCOPED_TRACE(run.path.string());
    const RunMemoryEstimate estimate = find_task(run.job.task)->estimate_run_bytes(run.job);
    const double held = record_bytes(run.record);
    EXPECT_GE(estimate.record_bytes, held);
    EXPECT_GE(estimate.peak(1.0), held);
  }
  for (const TaskDefinition& task : registered_tasks()) {
    EXPECT_EQ(checked.count(std::string(task.table.name)), 1u)
        << "no CI job (jobs/ci*.toml) runs task " << task.table.name;
  }
}

// Every registered task declares, before any run, each metric its runs report:
// the same declarations its run records (RunRecord::metric_specs), in the fits'
// column order, each with a unit, a meaning and a range that holds every value
// of the run. A new task is checked by its CI job.
TEST(MetricSpecs, EveryTaskDeclaresEachMetricItsRunsReport) {
  const char* source_dir = std::getenv("GGK_SOURCE_DIR");
  if (source_dir == nullptr) GTEST_SKIP() << "GGK_SOURCE_DIR is not set (run through ctest)";
  std::set<std::string> checked;
  for (const CiRun& run : ci_runs(source_dir)) {
    SCOPED_TRACE(run.path.string());
    const TaskDefinition* task = find_task(run.job.task);
    ASSERT_NE(task->metric_specs, nullptr);
    const std::vector<MetricSpec> declared = task->metric_specs(run.job);
    ASSERT_EQ(declared.size(), run.record.metric_specs.size());
    for (std::size_t m = 0; m < declared.size(); ++m) {
      const MetricSpec& spec = declared[m];
      EXPECT_EQ(spec.name, run.record.metric_specs[m].name);
      EXPECT_EQ(spec.kind, run.record.metric_specs[m].kind) << spec.name;
      EXPECT_EQ(spec.low, run.record.metric_specs[m].low) << spec.name;
      EXPECT_EQ(spec.high, run.record.metric_specs[m].high) << spec.name;
      EXPECT_FALSE(spec.unit.empty()) << spec.name;
      EXPECT_FALSE(spec.meaning.empty()) << spec.name;
      EXPECT_LE(spec.low, spec.high) << spec.name;
    }
    ASSERT_FALSE(run.record.fits.empty());
    for (const FitRecord& fit : run.record.fits) {
      ASSERT_EQ(fit.metrics.size(), declared.size());
      for (std::size_t m = 0; m < declared.size(); ++m) {
        const auto& [name, value] = fit.metrics[m];
        EXPECT_EQ(name, declared[m].name);
        if (std::isnan(value)) continue;
        EXPECT_GE(value, declared[m].low) << name;
        EXPECT_LE(value, declared[m].high) << name;
        if (declared[m].integer) {
          EXPECT_EQ(value, std::trunc(value)) << name;
        }
        if (declared[m].kind == MetricKind::kIndicator) {
          EXPECT_TRUE(value == 0.0 || value == 1.0) << name << " = " << value;
        }
      }
    }
    checked.insert(run.job.task);
  }
  for (const TaskDefinition& task : registered_tasks()) {
    EXPECT_EQ(checked.count(std::string(task.table.name)), 1u)
        << "no CI job (jobs/ci*.toml) runs task " << task.table.name;
  }
}

// The kinds the tasks declare: the shares of states or episodes are fractions,
// a named start's success an indicator (Wilson's interval in `ggk info`), the
// rest means; and the ranges the protocols derive from the job.
TEST(MetricSpecs, RatesFractionsAndRangesFollowTheProtocol) {
  ContinuousEnvironment env;
  env.ended_metric = "fall_fraction";
  env.reward_low = -1.0;
  env.reward_high = 0.0;
  ContinuousProtocol continuous;
  continuous.test_max_steps = 3000;
  const std::vector<MetricSpec> pendulum = continuous_metric_specs(env, continuous);
  EXPECT_EQ(declared_kind(pendulum, "fall_fraction"), MetricKind::kFraction);
  EXPECT_EQ(declared_kind(pendulum, "mean_return"), MetricKind::kMean);
  const MetricSpec* steps = find_metric_spec(pendulum, "mean_steps");
  ASSERT_NE(steps, nullptr);
  EXPECT_EQ(steps->high, 3000.0);
  const MetricSpec* return_spec = find_metric_spec(pendulum, "mean_return");
  EXPECT_EQ(return_spec->low, -3000.0);
  EXPECT_EQ(return_spec->high, 0.0);
  env.reward_low = -kUnbounded;  // a task that knows no bound on its rewards
  EXPECT_EQ(find_metric_spec(continuous_metric_specs(env, continuous), "mean_return")->low,
            -kUnbounded);

  DiscreteProtocol discrete;
  discrete.test_max_steps = 150;
  const std::string named[] = {"A"};
  const std::vector<MetricSpec> arm = discrete_metric_specs({}, named, discrete);
  EXPECT_EQ(declared_kind(arm, "success_rate"), MetricKind::kFraction);  // of the start states
  EXPECT_EQ(declared_kind(arm, "success_from_A"), MetricKind::kIndicator);
  EXPECT_EQ(declared_kind(arm, "steps_from_A"), MetricKind::kMean);
  EXPECT_EQ(find_metric_spec(arm, "mean_steps_to_goal")->high, 150.0);
  EXPECT_EQ(declared_kind(arm, "lspi_iterations"), MetricKind::kMean);
  EXPECT_TRUE(find_metric_spec(arm, "lspi_iterations")->integer);
  EXPECT_EQ(find_metric_spec(arm, "no_such_metric"), nullptr);
}

}  // namespace
}  // namespace ggk::engine
