// The registered tasks (engine/tasks/task_list.hpp): each one complete, and what
// they declare (metrics: kind, unit, meaning, range, tasks/metric_spec.hpp;
// datasets: axes, units, meaning, tasks/dataset_spec.hpp). Every test here walks
// the task list, so a new task is checked without naming it; the checks are
// functions of a TaskDefinition, and ANewTaskIsCheckedWithoutBeingNamed shows
// them catching a throwaway task's omissions.

#include "engine/tasks/task_list.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <set>
#include <span>
#include <string>
#include <vector>

#include "engine/job/job_error.hpp"
#include "engine/job/job_file.hpp"
#include "engine/run/job_runner.hpp"
#include "engine/store/dataset_schema.hpp"
#include "engine/tasks/continuous_protocol.hpp"
#include "engine/tasks/discrete_protocol.hpp"
#include "engine/tasks/record_bytes.hpp"

namespace ggk::engine {
namespace {

namespace fs = std::filesystem;

// The names of `tasks` that `covered` lacks: the tasks a per-task test missed.
std::vector<std::string> uncovered(std::span<const TaskDefinition> tasks,
                                   const std::set<std::string>& covered) {
  std::vector<std::string> missed;
  for (const TaskDefinition& task : tasks) {
    if (covered.count(std::string(task.table.name)) == 0) missed.emplace_back(task.table.name);
  }
  return missed;
}

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
  EXPECT_EQ(uncovered(registered_tasks(), shipped), std::vector<std::string>{})
      << "no job in jobs/ runs these tasks";
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
  EXPECT_EQ(uncovered(registered_tasks(), checked), std::vector<std::string>{})
      << "no CI job (jobs/ci*.toml) runs these tasks";
}

// What `task` declares of its metrics, checked against one run of its CI job: the
// same declarations its run records (RunRecord::metric_specs), in the fits'
// column order, each with a unit, a meaning and a range that holds every value
// of the run. One line per problem; none when the declarations are right.
std::vector<std::string> metric_declaration_problems(const TaskDefinition& task, const CiRun& run) {
  std::vector<std::string> problems;
  const auto problem = [&](const std::string& name, const std::string& what) {
    problems.push_back(name + ": " + what);
  };
  if (task.metric_specs == nullptr) return {"no metric_specs"};
  const std::vector<MetricSpec> declared = task.metric_specs(run.job);
  if (declared.size() != run.record.metric_specs.size()) {
    return {std::to_string(declared.size()) + " metrics declared, the run records " +
            std::to_string(run.record.metric_specs.size())};
  }
  for (std::size_t m = 0; m < declared.size(); ++m) {
    const MetricSpec& spec = declared[m];
    const MetricSpec& recorded = run.record.metric_specs[m];
    if (spec.name != recorded.name) problem(spec.name, "the run records " + recorded.name);
    if (spec.kind != recorded.kind) problem(spec.name, "another kind than the run's");
    if (spec.low != recorded.low || spec.high != recorded.high) {
      problem(spec.name, "another range than the run's");
    }
    if (spec.unit.empty()) problem(spec.name, "no unit");
    if (spec.meaning.empty()) problem(spec.name, "no meaning");
    if (!(spec.low <= spec.high)) problem(spec.name, "low above high");
  }
  if (run.record.fits.empty()) problems.push_back("the run has no fits");
  for (const FitRecord& fit : run.record.fits) {
    if (fit.metrics.size() != declared.size()) {
      problems.push_back("a fit reports " + std::to_string(fit.metrics.size()) + " metrics");
      continue;
    }
    for (std::size_t m = 0; m < declared.size(); ++m) {
      const auto& [name, value] = fit.metrics[m];
      if (name != declared[m].name) problem(name, "reported where " + declared[m].name + " is");
      if (std::isnan(value)) continue;
      if (value < declared[m].low || value > declared[m].high) {
        problem(name, std::to_string(value) + " outside its declared range");
      }
      if (declared[m].integer && value != std::trunc(value)) {
        problem(name, std::to_string(value) + " is not a whole number");
      }
      if (declared[m].kind == MetricKind::kIndicator && value != 0.0 && value != 1.0) {
        problem(name, std::to_string(value) + " is not 0 or 1");
      }
    }
  }
  return problems;
}

// The arrays of a run of `task` that its declarations (TaskDefinition::datasets)
// and the store's leave undeclared, or declare with another number of axes: the
// datasets the writer would refuse (store/dataset_schema.hpp).
std::vector<std::string> undeclared_datasets(const TaskDefinition& task, const RunRecord& record) {
  std::vector<std::string> undeclared;
  const auto check = [&](const std::string& path, const NamedArray& array) {
    const DatasetSpec* spec = dataset_spec_of(path, task.datasets);
    if (spec == nullptr) {
      undeclared.push_back(path);
    } else if (dims_rank(spec->dims) != array.shape.size()) {
      undeclared.push_back(path + " (" + std::to_string(array.shape.size()) + " axes, declared " +
                           std::string(spec->dims) + ")");
    }
  };
  for (const NamedArray& array : record.arrays) check(array.name, array);
  for (const FitRecord& fit : record.fits) {
    for (const NamedArray& array : fit.arrays) check("fits/basis/point/" + array.name, array);
  }
  return undeclared;
}

// Every registered task declares, before any run, each metric its runs report
// (metric_declaration_problems), checked by its CI job.
TEST(MetricSpecs, EveryTaskDeclaresEachMetricItsRunsReport) {
  const char* source_dir = std::getenv("GGK_SOURCE_DIR");
  if (source_dir == nullptr) GTEST_SKIP() << "GGK_SOURCE_DIR is not set (run through ctest)";
  std::set<std::string> checked;
  for (const CiRun& run : ci_runs(source_dir)) {
    EXPECT_EQ(metric_declaration_problems(*find_task(run.job.task), run),
              std::vector<std::string>{})
        << run.path;
    checked.insert(run.job.task);
  }
  EXPECT_EQ(uncovered(registered_tasks(), checked), std::vector<std::string>{})
      << "no CI job (jobs/ci*.toml) runs these tasks";
}

// Every registered task declares each array its runs add (undeclared_datasets),
// checked by its CI job: a new task's array is named here, not by the writer
// refusing a run.
TEST(DatasetSpecs, EveryTaskDeclaresEachArrayItsRunsAdd) {
  const char* source_dir = std::getenv("GGK_SOURCE_DIR");
  if (source_dir == nullptr) GTEST_SKIP() << "GGK_SOURCE_DIR is not set (run through ctest)";
  std::set<std::string> checked;
  for (const CiRun& run : ci_runs(source_dir)) {
    EXPECT_EQ(undeclared_datasets(*find_task(run.job.task), run.record), std::vector<std::string>{})
        << run.path;
    checked.insert(run.job.task);
  }
  EXPECT_EQ(uncovered(registered_tasks(), checked), std::vector<std::string>{})
      << "no CI job (jobs/ci*.toml) runs these tasks";
}

// A task added to the list is checked without any test naming it: a throwaway
// task (the chain under another name) that has no CI job, drops a declaration of
// a metric and of an array, and declares a range its values leave, is caught by
// each of the checks above.
TEST(TaskList, ANewTaskIsCheckedWithoutBeingNamed) {
  const char* source_dir = std::getenv("GGK_SOURCE_DIR");
  if (source_dir == nullptr) GTEST_SKIP() << "GGK_SOURCE_DIR is not set (run through ctest)";
  const CiRun* chain_run = nullptr;
  for (const CiRun& run : ci_runs(source_dir)) {
    if (run.job.task == "chain") chain_run = &run;
  }
  ASSERT_NE(chain_run, nullptr);
  const TaskDefinition& chain = *find_task("chain");
  ASSERT_EQ(metric_declaration_problems(chain, *chain_run), std::vector<std::string>{});
  ASSERT_EQ(undeclared_datasets(chain, chain_run->record), std::vector<std::string>{});

  TaskDefinition throwaway = chain;
  throwaway.table.name = "throwaway";
  std::vector<TaskDefinition> tasks(registered_tasks().begin(), registered_tasks().end());
  tasks.push_back(throwaway);
  std::set<std::string> covered;
  for (const TaskDefinition& task : registered_tasks()) covered.emplace(task.table.name);
  EXPECT_EQ(uncovered(tasks, covered), std::vector<std::string>{"throwaway"});

  throwaway.datasets.erase(throwaway.datasets.begin());  // the chain's own: optimal_actions
  EXPECT_EQ(undeclared_datasets(throwaway, chain_run->record),
            std::vector<std::string>{"optimal_actions"});

  throwaway.metric_specs = [](const JobSpec& job) {
    std::vector<MetricSpec> specs = find_task("chain")->metric_specs(job);
    specs.pop_back();
    return specs;
  };
  EXPECT_EQ(metric_declaration_problems(throwaway, *chain_run).size(), 1u);
  throwaway.metric_specs = [](const JobSpec& job) {
    std::vector<MetricSpec> specs = find_task("chain")->metric_specs(job);
    for (MetricSpec& spec : specs) spec.high = spec.low;  // every value left outside
    return specs;
  };
  EXPECT_FALSE(metric_declaration_problems(throwaway, *chain_run).empty());
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
