#include "support/shipped_jobs.hpp"

#include <algorithm>
#include <cstdlib>

#include "engine/job/job_error.hpp"
#include "engine/job/job_file.hpp"
#include "engine/tasks/task_list.hpp"

namespace ggk::test_support {

namespace fs = std::filesystem;

std::vector<std::string> registered_task_names() {
  std::vector<std::string> names;
  for (const engine::TaskDefinition& task : engine::registered_tasks()) {
    names.emplace_back(task.table.name);
  }
  return names;
}

std::optional<fs::path> ci_job_for(const std::string& task) {
  const char* source_dir = std::getenv("GGK_SOURCE_DIR");
  if (source_dir == nullptr) return std::nullopt;
  std::vector<fs::path> jobs;
  for (const auto& entry : fs::directory_iterator(fs::path(source_dir) / "jobs")) {
    const std::string name = entry.path().filename().string();
    if (name.starts_with("ci") && entry.path().extension() == ".toml") jobs.push_back(entry.path());
  }
  std::sort(jobs.begin(), jobs.end());
  for (const fs::path& path : jobs) {
    engine::JobLoadOptions options;
    options.check_output = false;
    try {
      if (engine::load_job_file(path, engine::task_tables(), options).task == task) return path;
    } catch (const engine::JobError&) {
      // a study: `ggk run` reads it as one (engine/job/study.hpp)
    }
  }
  return std::nullopt;
}

std::string parameter_name(std::string name) {
  std::replace(name.begin(), name.end(), '-', '_');
  return name;
}

}  // namespace ggk::test_support
