// The registered tasks (engine/tasks/task_list.hpp): each one complete, and the
// metric kinds they declare: the rates (which get Wilson's or a clipped interval
// in `ggk info`) and the means.

#include "engine/tasks/task_list.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "engine/job/job_error.hpp"
#include "engine/job/job_file.hpp"
#include "engine/run/job_runner.hpp"
#include "engine/tasks/discrete_protocol.hpp"
#include "engine/tasks/khepera/khepera_task.hpp"
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

// Every registered task's estimate covers what one run of its shipped CI job
// (jobs/ci*.toml) holds in its record, so a new task cannot ship an estimate
// that the runner's memory check would trust below the truth.
TEST(MemoryCheck, EveryTasksEstimateCoversItsCiRecord) {
  const char* source_dir = std::getenv("GGK_SOURCE_DIR");
  if (source_dir == nullptr) GTEST_SKIP() << "GGK_SOURCE_DIR is not set (run through ctest)";
  std::set<std::string> checked;
  std::vector<fs::path> jobs;
  for (const auto& entry : fs::directory_iterator(fs::path(source_dir) / "jobs")) {
    if (entry.path().filename().string().starts_with("ci")) jobs.push_back(entry.path());
  }
  std::sort(jobs.begin(), jobs.end());
  for (const fs::path& path : jobs) {
    JobLoadOptions options;
    options.check_output = false;
    JobSpec job;
    try {
      job = load_job_file(path, task_tables(), options);
    } catch (const JobError&) {
      continue;  // a study
    }
    if (!checked.insert(job.task).second) continue;
    SCOPED_TRACE(path.string());
    const RunMemoryEstimate estimate = find_task(job.task)->estimate_run_bytes(job);
    const double held = record_bytes(compute_run(job, 0));
    EXPECT_GE(estimate.record_bytes, held);
    EXPECT_GE(estimate.peak(1.0), held);
  }
  for (const TaskDefinition& task : registered_tasks()) {
    EXPECT_EQ(checked.count(std::string(task.table.name)), 1u)
        << "no CI job (jobs/ci*.toml) runs task " << task.table.name;
  }
}

TEST(MetricKind, EachTaskDeclaresItsRatesAndFractions) {
  EXPECT_EQ(metric_kind("maze", "success_rate"), MetricKind::kFraction);  // of the states
  EXPECT_EQ(metric_kind("arm", "success_rate"), MetricKind::kFraction);
  EXPECT_EQ(metric_kind("arm", "success_from_A"), MetricKind::kRate);
  EXPECT_EQ(metric_kind("arm", "steps_from_A"), MetricKind::kMean);
  EXPECT_EQ(metric_kind("khepera", "collision_fraction"), MetricKind::kFraction);  // of episodes
  EXPECT_EQ(metric_kind("khepera", "mean_return"), MetricKind::kMean);
  EXPECT_EQ(metric_kind("chain", "optimal_action_fraction"), MetricKind::kFraction);
  EXPECT_EQ(metric_kind("pendulum", "fall_fraction"), MetricKind::kFraction);  // of episodes
  EXPECT_EQ(metric_kind("pendulum", "mean_steps"), MetricKind::kMean);
  EXPECT_EQ(metric_kind("mountain_car", "success_rate"), MetricKind::kFraction);
  EXPECT_EQ(metric_kind("acrobot", "success_rate"), MetricKind::kFraction);
  EXPECT_EQ(metric_kind("acrobot", "mean_return"), MetricKind::kMean);
}

TEST(MetricKind, EveryOtherMetricIsAMean) {
  for (const std::string& name : discrete_metric_names()) {
    if (name == "success_rate") continue;
    EXPECT_EQ(metric_kind("maze", name), MetricKind::kMean) << name;
  }
  for (const std::string& name : khepera_metric_names()) {
    if (name == "collision_fraction") continue;
    EXPECT_EQ(metric_kind("khepera", name), MetricKind::kMean) << name;
  }
  // The wall time every summary carries, and what no task declares.
  EXPECT_EQ(metric_kind("maze", "fit_seconds"), MetricKind::kMean);
  EXPECT_EQ(metric_kind("no_such_task", "success_rate"), MetricKind::kMean);
}

}  // namespace
}  // namespace ggk::engine
