// The registered tasks (engine/tasks/task_list.hpp): each one complete, and the
// metric kinds they declare: the rates (which get Wilson's or a clipped interval
// in `ggk info`) and the means.

#include "engine/tasks/task_list.hpp"

#include <gtest/gtest.h>

#include <string>

#include "engine/tasks/discrete_protocol.hpp"
#include "engine/tasks/khepera/khepera_task.hpp"

namespace ggk::engine {
namespace {

TEST(MemoryCheck, EveryTaskEstimatesItsRuns) {
  for (const TaskDefinition& task : registered_tasks()) {
    EXPECT_NE(task.estimate_run_bytes, nullptr) << task.table.name;
  }
}

TEST(MetricKind, EachTaskDeclaresItsRatesAndFractions) {
  EXPECT_EQ(metric_kind("maze", "success_rate"), MetricKind::kFraction);  // of the states
  EXPECT_EQ(metric_kind("arm", "success_rate"), MetricKind::kFraction);
  EXPECT_EQ(metric_kind("arm", "success_from_A"), MetricKind::kRate);
  EXPECT_EQ(metric_kind("arm", "steps_from_A"), MetricKind::kMean);
  EXPECT_EQ(metric_kind("khepera", "collision_fraction"), MetricKind::kFraction);  // of episodes
  EXPECT_EQ(metric_kind("khepera", "mean_return"), MetricKind::kMean);
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
