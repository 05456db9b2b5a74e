#include "engine/store/configuration_groups.hpp"

#include <map>
#include <string>
#include <vector>

#include "engine/job/usage_error.hpp"
#include "engine/store/one_line.hpp"
#include "engine/store/run_store.hpp"

namespace ggk::engine {

namespace fs = std::filesystem;

namespace {

// A configuration's study_values ("key = value" lines) on one line of a message:
// "maze.slip = 0.1, maze.series = 40" (cut when a damaged file holds a long text).
std::string values_on_one_line(const std::string& values) {
  std::string text;
  std::string::size_type from = 0;
  while (from < values.size()) {
    std::string::size_type end = values.find('\n', from);
    if (end == std::string::npos) end = values.size();
    if (end > from) text += (text.empty() ? "" : ", ") + values.substr(from, end - from);
    from = end + 1;
  }
  return one_line(text);
}

}  // namespace

std::vector<ConfigurationGroup> configuration_groups(const Hdf5File& file, const Study& study,
                                                     const fs::path& output) {
  std::vector<ConfigurationGroup> found;
  if (study.configurations.front().job.configuration_group.empty()) return found;
  const std::string task_group = "/" + study.job().task;
  std::map<std::string, std::size_t> by_values;
  for (std::size_t c = 0; c < study.configurations.size(); ++c) {
    by_values.emplace(study_values_text(study.configurations[c].assignments), c);
  }
  std::vector<bool> has_group(study.configurations.size(), false);
  for (const std::string& name : file.member_names(task_group)) {
    const bool moving =
        name.starts_with(kMovingPrefix) &&
        is_configuration_group_name(std::string_view(name).substr(kMovingPrefix.size()));
    if (!moving && !is_configuration_group_name(name)) continue;
    const std::string group = task_group + "/" + name;
    const std::string values = study_values_of(file, group.substr(1)).value_or(std::string());
    const auto configuration = by_values.find(values);
    if (configuration == by_values.end()) {
      throw UsageError("cannot resume " + output.string() + ": its group " + group +
                       " holds the run configuration " +
                       (values.empty() ? std::string("(no study_values)")
                                       : "{" + values_on_one_line(values) + "}") +
                       ", which this job does not have; resume with the job that has it, or "
                       "write to another -o");
    }
    if (has_group[configuration->second]) {
      throw UsageError("cannot resume " + output.string() +
                       ": two of its groups hold the run "
                       "configuration {" +
                       values + "} (damaged); write to another -o");
    }
    has_group[configuration->second] = true;
    found.push_back({name, configuration->second});
  }
  return found;
}

void write_configuration_group(Hdf5File& file, const RunConfiguration& configuration) {
  write_configuration_group(file, runs_location(configuration.job), configuration.index,
                            study_values_text(configuration.assignments));
}

// Two steps: out of the way (moving_*), then into place (header).
void align_configurations(Hdf5File& file, const Study& study, const fs::path& output) {
  if (study.configurations.front().job.configuration_group.empty()) return;
  const std::string task_group = "/" + study.job().task;
  std::vector<ConfigurationGroup> found = configuration_groups(file, study, output);
  std::vector<bool> has_group(study.configurations.size(), false);
  for (const ConfigurationGroup& group : found) has_group[group.configuration] = true;
  constexpr std::string_view kMoving = kMovingPrefix;
  for (auto& [name, c] : found) {  // out of the way
    const std::string& target = study.configurations[c].job.configuration_group;
    if (name == target || name == std::string(kMoving) + target) continue;
    file.move(task_group + "/" + name, task_group + "/" + std::string(kMoving) + target);
    name = std::string(kMoving) + target;
  }
  for (auto& [name, c] : found) {  // into place
    const RunConfiguration& configuration = study.configurations[c];
    if (name != configuration.job.configuration_group) {
      file.move(task_group + "/" + name, "/" + runs_location(configuration.job));
    }
    if (!records_configuration(file, runs_location(configuration.job), configuration.index)) {
      write_configuration_group(file, configuration);
    }
  }
  for (std::size_t c = 0; c < study.configurations.size(); ++c) {
    if (!has_group[c]) write_configuration_group(file, study.configurations[c]);
  }
  file.flush();
}

}  // namespace ggk::engine
