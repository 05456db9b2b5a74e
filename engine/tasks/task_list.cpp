#include "engine/tasks/task_list.hpp"

#include <vector>

#include "engine/tasks/acrobot/acrobot_task.hpp"
#include "engine/tasks/arm/arm_task.hpp"
#include "engine/tasks/chain/chain_task.hpp"
#include "engine/tasks/khepera/khepera_task.hpp"
#include "engine/tasks/maze/maze_task.hpp"
#include "engine/tasks/mountain_car/mountain_car_task.hpp"
#include "engine/tasks/pendulum/pendulum_task.hpp"
#if GGK_WITH_PYTHON
#include "engine/tasks/python_env/python_env_task.hpp"
#endif

namespace ggk::engine {

namespace {

// The one list: a task's definition per line.
const std::vector<TaskDefinition>& all_tasks() {
  static const std::vector<TaskDefinition> tasks = {
    maze_task_definition(),
    arm_task_definition(),
    khepera_task_definition(),
    chain_task_definition(),
    pendulum_task_definition(),
    mountain_car_task_definition(),
    acrobot_task_definition(),
#if GGK_WITH_PYTHON
    python_env_task_definition(),
#endif
  };
  return tasks;
}

}  // namespace

std::span<const TaskDefinition> registered_tasks() {
  return all_tasks();
}

std::span<const TaskTable> task_tables() {
  static const std::vector<TaskTable> tables = [] {
    std::vector<TaskTable> result;
    for (const TaskDefinition& task : all_tasks()) result.push_back(task.table);
    return result;
  }();
  return tables;
}

const TaskDefinition* find_task(std::string_view name) {
  for (const TaskDefinition& task : all_tasks()) {
    if (task.table.name == name) return &task;
  }
  return nullptr;
}

}  // namespace ggk::engine
