#include "engine/store/results_contents.hpp"

#include <charconv>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>
#include <variant>
#include <vector>

#include "engine/job/usage_error.hpp"
#include "engine/store/metric_specs_table.hpp"

namespace ggk::engine {
namespace {

// The shortest text that reads back as `v` (1e-06, not 9.9999999999999995e-07).
std::string exact_text(double v) {
  char text[64];
  const auto result = std::to_chars(text, text + sizeof text, v);
  return std::string(text, result.ptr);
}

}  // namespace

double as_double(const TableValue& v) {
  if (const auto* d = std::get_if<double>(&v)) return *d;
  if (const auto* i = std::get_if<std::int32_t>(&v)) return *i;
  if (const auto* l = std::get_if<std::int64_t>(&v)) return static_cast<double>(*l);
  return std::nan("");
}

std::string as_text(const TableValue& v) {
  if (const auto* s = std::get_if<std::string>(&v)) return *s;
  if (const auto* d = std::get_if<double>(&v)) return exact_text(*d);
  return std::to_string(static_cast<long long>(as_double(v)));
}

// The rows of every complete run (what the summary holds once the job ends, so
// also what a running or killed job has done so far). Their columns: run,
// sweep_point, the point's axes up to status, then the metrics and fit_seconds.
ResultsContents read_contents(const Hdf5File& file) {
  ResultsContents contents;
  try {
    contents.header = read_results_header(file);
  } catch (const ResultsHeaderError& e) {
    throw UsageError(e.what());
  }
  const std::string& task = contents.header.task;
  const auto runs = static_cast<std::int32_t>(contents.header.runs);
  const std::vector<std::string> locations = runs_locations(file, task);
  if (locations.front() != task) contents.configurations = locations.size();
  contents.summary_written = file.exists("/" + task + "/summary");
  std::vector<TableColumn> columns;
  // Columns by name: run, sweep_point, the point's axes (the built-in ones,
  // then a study's keys), status, the metrics. A point of a study is its
  // configuration's sweep point.
  std::size_t point_column = 1, status_column = 0;
  std::optional<std::vector<MetricSpec>> declared;
  for (std::size_t l = 0; l < locations.size(); ++l) {
    const auto configuration = static_cast<std::int64_t>(l);
    for (const std::int32_t run : complete_runs(file, locations[l], runs)) {
      ++contents.complete_runs;
      const std::string table = run_group(locations[l], run) + "/fit_metrics";
      try {
        unite_run_metric_specs(file, run_group(locations[l], run), declared);
      } catch (const std::runtime_error& e) {
        throw UsageError(e.what());
      }
      if (columns.empty()) {
        columns = file.read_table_columns(table);
        for (std::size_t c = 0; c < columns.size(); ++c) {
          if (columns[c].name == "status") status_column = c;
          if (columns[c].name == "sweep_point") point_column = c;
        }
        for (std::size_t c = point_column + 1; c < status_column; ++c) {
          contents.axis_names.push_back(columns[c].name);
        }
        for (std::size_t c = status_column + 1; c < columns.size(); ++c) {
          contents.metric_names.push_back(columns[c].name);
        }
      }
      for (const TableRow& row : file.read_table(table)) {
        FitRow fit;
        fit.run = static_cast<std::int64_t>(as_double(row[0]));
        fit.configuration = static_cast<std::int32_t>(configuration);
        fit.point = (configuration << 32) + static_cast<std::int64_t>(as_double(row[point_column]));
        for (std::size_t c = point_column + 1; c < status_column; ++c) {
          fit.key.push_back(as_text(row[c]));
        }
        fit.status = fit_status_from_text(as_text(row[status_column]));
        for (std::size_t c = status_column + 1; c < columns.size(); ++c) {
          fit.values.push_back(as_double(row[c]));
        }
        contents.fits.push_back(std::move(fit));
      }
    }
  }
  contents.metrics_declared = declared.has_value();
  for (const std::string& name : contents.metric_names) {
    const MetricSpec* spec = declared ? find_metric_spec(*declared, name) : nullptr;
    contents.metric_specs.push_back(spec != nullptr ? *spec : legacy_metric_spec(name));
  }
  return contents;
}

}  // namespace ggk::engine
