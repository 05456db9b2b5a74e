#pragma once
// The shipped jobs (jobs/*.toml) by task, for tests that cover every registered
// task: the task list (engine/tasks/task_list.hpp) is the one list, so a new
// task is covered by such a test as soon as it is registered and ships a job.

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace ggk::test_support {

// The names of the registered tasks, in the list's order.
std::vector<std::string> registered_task_names();

// The CI-sized job of `task`: the first jobs/ci*.toml (by name) that is a plain
// job of the task (not a study); nullopt when GGK_SOURCE_DIR is unset or none is.
std::optional<std::filesystem::path> ci_job_for(const std::string& task);

// A test parameter's name for a task or job ("mountain_car", "ci_arm").
std::string parameter_name(std::string name);

}  // namespace ggk::test_support
