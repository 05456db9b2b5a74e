#include "engine/store/results_layout.hpp"

#include <algorithm>
#include <array>
#include <cstdint>

namespace ggk::engine {

namespace {

constexpr std::string_view kInputPrefix = "input:";
constexpr std::array<std::string_view, 8> kProvenance = {"job_file",
                                                         "git",
                                                         "ggk_version",
                                                         "blas",
                                                         "runs_selected",
                                                         "rules",
                                                         "configurations_selected",
                                                         "adaptive_cells"};

// Reads the root attribute `name` with `read`; a missing one is an error when
// `required`, else `fallback`. Every failure names the file and the attribute.
template <class T, class Read>
T root_attribute(const Hdf5File& file, std::string_view name, bool required, T fallback,
                 Read&& read) {
  const std::string prefix = file.path().string() + " is not a ggk results file";
  if (!file.has_attribute("/", name)) {
    if (!required) return fallback;
    throw ResultsHeaderError(prefix + " (no '" + std::string(name) + "' attribute)");
  }
  try {
    return read(name);
  } catch (const std::runtime_error& e) {
    throw ResultsHeaderError(prefix + ": its '" + std::string(name) + "' attribute: " + e.what());
  }
}

std::string string_at(const Hdf5File& file, std::string_view name, bool required) {
  return root_attribute<std::string>(file, name, required, {}, [&](std::string_view n) {
    return file.read_string_attribute("/", n);
  });
}

std::int64_t int64_at(const Hdf5File& file, std::string_view name, bool required,
                      std::int64_t fallback) {
  return root_attribute<std::int64_t>(file, name, required, fallback, [&](std::string_view n) {
    return file.read_int64_attribute("/", n);
  });
}

// The attributes that say which job the file holds (a grown study rewrites them).
constexpr std::array<const char*, 6> kJobAttributes = {
    "job", "job_file", "runs", "job_sweeps", "job_overrides", "job_resolved"};

void write_job_attributes(Hdf5File& file, const ResultsHeader& header) {
  file.write_string_attribute("/", "job", header.job);
  file.write_string_attribute("/", "job_file", header.job_file);
  file.write_int64_attribute("/", "runs", header.runs);
  if (!header.job_sweeps.empty()) {
    file.write_string_attribute("/", "job_sweeps", header.job_sweeps);
  }
  if (!header.job_overrides.empty()) {
    file.write_string_attribute("/", "job_overrides", header.job_overrides);
  }
  if (!header.job_resolved.empty()) {
    file.write_string_attribute("/", "job_resolved", header.job_resolved);
  }
}

}  // namespace

void write_results_header(Hdf5File& file, const ResultsHeader& header) {
  write_job_attributes(file, header);
  for (const RecordedInput& input : header.inputs) {
    file.write_string_attribute("/", input_attribute_name(input.key), input.text);
  }
  file.write_string_attribute("/", "ggk_version", header.ggk_version);
  file.write_string_attribute("/", "git", header.git);
  if (!header.blas.empty()) file.write_string_attribute("/", "blas", header.blas);
  file.write_string_attribute("/", "created", header.created);
  file.write_string_attribute("/", "task", header.task);
  file.write_int64_attribute("/", "layout", header.layout);
  file.write_int64_attribute("/", "rules", header.rules);
  write_runs_selected(file, header.runs_selected);
  write_configurations_selected(file, header.configurations_selected);
}

void rewrite_job_attributes(Hdf5File& file, const ResultsHeader& header) {
  for (const char* name : kJobAttributes) {
    if (file.has_attribute("/", name)) file.remove_attribute("/", name);
  }
  write_job_attributes(file, header);
}

ResultsHeader read_results_header(const Hdf5File& file) {
  ResultsHeader header;
  // job and task first: a file without them is not a results file at all.
  header.job = string_at(file, "job", true);
  header.task = string_at(file, "task", true);
  header.job_file = string_at(file, "job_file", true);
  header.runs = int64_at(file, "runs", true, 0);
  if (header.runs < 1 || header.runs > INT32_MAX) {
    throw ResultsHeaderError(file.path().string() +
                             " is not a ggk results file: its 'runs' attribute is " +
                             std::to_string(header.runs) + ", not a run count (1 .. 2147483647)");
  }
  header.ggk_version = string_at(file, "ggk_version", true);
  header.git = string_at(file, "git", true);
  header.created = string_at(file, "created", true);
  header.blas = string_at(file, "blas", false);
  header.job_overrides = string_at(file, "job_overrides", false);
  header.job_sweeps = string_at(file, "job_sweeps", false);
  header.job_resolved = string_at(file, "job_resolved", false);
  header.layout = int64_at(file, "layout", false, 1);
  header.rules = int64_at(file, "rules", false, 0);
  if (header.rules == 0) header.rules = rules_of_unmarked_file(header.git);
  header.runs_selected = root_attribute<std::optional<RunsSelected>>(
      file, "runs_selected", false, std::nullopt,
      [&](std::string_view name) -> std::optional<RunsSelected> {
        const std::vector<std::int64_t> range = file.read_int64_array_attribute("/", name);
        if (range.size() != 2) {
          throw std::runtime_error("holds " + std::to_string(range.size()) +
                                   " values, not the two of a range [A, B)");
        }
        return RunsSelected{range[0], range[1]};
      });
  if (file.has_attribute("/", "configurations_selected")) {
    ConfigurationsSelected selected;
    selected.configurations = root_attribute<std::vector<std::int64_t>>(
        file, "configurations_selected", true, {},
        [&](std::string_view name) { return file.read_int64_array_attribute("/", name); });
    selected.cells = int64_at(file, "adaptive_cells", true, 0);
    header.configurations_selected = std::move(selected);
  }
  for (const std::string& name : file.attribute_names("/")) {  // sorted by name
    if (name.starts_with(kInputPrefix)) {
      header.inputs.push_back({name.substr(kInputPrefix.size()), string_at(file, name, true)});
    }
  }
  return header;
}

void write_runs_selected(Hdf5File& file, const std::optional<RunsSelected>& runs_selected) {
  if (file.has_attribute("/", "runs_selected")) file.remove_attribute("/", "runs_selected");
  if (runs_selected) file.write_int64_array_attribute("/", "runs_selected", *runs_selected);
}

void write_configurations_selected(Hdf5File& file,
                                   const std::optional<ConfigurationsSelected>& selected) {
  for (const char* name : {"configurations_selected", "adaptive_cells"}) {
    if (file.has_attribute("/", name)) file.remove_attribute("/", name);
  }
  if (!selected) return;
  file.write_int64_array_attribute("/", "configurations_selected", selected->configurations);
  file.write_int64_attribute("/", "adaptive_cells", selected->cells);
}

std::string layout_mismatch(std::int64_t layout) {
  if (layout == kLayoutVersion) return {};
  return "it has results layout " + std::to_string(layout) + " (" +
         (layout < kLayoutVersion ? "written by an older ggk: fit groups named by the swept axes, "
                                    "fixed-length strings, integers stored as float64"
                                  : "written by a newer ggk") +
         ") and this ggk writes layout " + std::to_string(kLayoutVersion) +
         ", so it cannot add runs to it (ggk info, diff and verify still read it)";
}

std::string input_attribute_name(std::string_view key) {
  return std::string(kInputPrefix) + std::string(key);
}

RootAttributeRole root_attribute_role(std::string_view name) {
  if (name == "created") return RootAttributeRole::kWallClock;
  if (std::find(kProvenance.begin(), kProvenance.end(), name) != kProvenance.end()) {
    return RootAttributeRole::kProvenance;
  }
  return RootAttributeRole::kResult;
}

std::string_view to_string(FitStatus status) {
  switch (status) {
    case FitStatus::kConverged:
      return "converged";
    case FitStatus::kMaxIterations:
      return "max_iterations";
    case FitStatus::kSolverFailed:
      return "solver_failed";
    case FitStatus::kInvalid:
      return "invalid";
    case FitStatus::kEnvironmentFailed:
      return "environment_failed";
  }
  return "unknown";
}

std::optional<FitStatus> fit_status_from_text(std::string_view text) {
  for (const FitStatus status :
       {FitStatus::kConverged, FitStatus::kMaxIterations, FitStatus::kSolverFailed,
        FitStatus::kInvalid, FitStatus::kEnvironmentFailed}) {
    if (text == to_string(status)) return status;
  }
  return std::nullopt;
}

bool is_failed(FitStatus status) {
  return status == FitStatus::kSolverFailed || status == FitStatus::kInvalid ||
         status == FitStatus::kEnvironmentFailed;
}

bool is_failed_status(std::string_view text) {
  const std::optional<FitStatus> status = fit_status_from_text(text);
  return status && is_failed(*status);
}

}  // namespace ggk::engine
