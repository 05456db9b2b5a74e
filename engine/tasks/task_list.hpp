#pragma once
// Every task ggk knows, in one list (task_list.cpp). Adding a task = a folder
// under engine/tasks/ that defines a TaskDefinition, and one line in that list.

#include <span>
#include <string_view>

#include "engine/job/task_table.hpp"
#include "engine/tasks/task_definition.hpp"

namespace ggk::engine {

// The registered tasks, in a fixed order (the order job-file messages list them).
std::span<const TaskDefinition> registered_tasks();

// Their job-file tables, for load_job_file() / parse_job().
std::span<const TaskTable> task_tables();

// The registered task called `name`, or nullptr.
const TaskDefinition* find_task(std::string_view name);

}  // namespace ggk::engine
