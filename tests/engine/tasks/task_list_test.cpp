// The registered tasks (engine/tasks/task_list.hpp): each one complete.

#include "engine/tasks/task_list.hpp"

#include <gtest/gtest.h>

namespace ggk::engine {
namespace {

TEST(MemoryCheck, EveryTaskEstimatesItsRuns) {
  for (const TaskDefinition& task : registered_tasks()) {
    EXPECT_NE(task.estimate_run_bytes, nullptr) << task.table.name;
  }
}

}  // namespace
}  // namespace ggk::engine
