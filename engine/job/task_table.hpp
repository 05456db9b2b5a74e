#pragma once
// A task's table in job files, as the job reader (job_file.hpp) sees it: the
// task's name (task = "<name>", which is also the name of its table [<name>]) and
// the parser of that table. The reader knows no task by name: it is handed the
// list of tables (engine/tasks/task_list.hpp gives every registered task's).

#include <any>
#include <filesystem>
#include <string_view>
#include <vector>

#include "engine/job/job_input.hpp"
#include "engine/job/toml_table_reader.hpp"

namespace ggk::engine {

// Reads the task's table of `job`, the job file's root table (whether an absent
// table means all defaults or an error is the task's choice). job_dir is the job
// file's folder, against which relative file names resolve; every file read is
// appended to `inputs`. Returns the task's configuration (any copyable type; the
// task reads it back with task_config_as<Config>()). Throws JobError.
using TaskTableParser = std::any (*)(const TomlTableReader& job,
                                     const std::filesystem::path& job_dir,
                                     std::vector<JobInput>& inputs);

// test_max_steps of every task: a greedy test walks at most this many steps from
// a start. The paper tests 100 steps (arm) and 150 (Khepera); a policy that
// reaches a goal of a deterministic task visits no state twice, and 10^6 steps
// cover the longest such path of a 1000 x 1000 maze. Beyond it a job is one
// that never ends, not a larger study.
inline constexpr IntegerRange kTestMaxStepsRange{1, 1'000'000};

struct TaskTable {
  std::string_view name;  // [A-Za-z0-9_]+, distinct from the job file's other top-level keys
  TaskTableParser parse = nullptr;
};

}  // namespace ggk::engine
