#include "engine/store/results_info.hpp"

#include <cmath>
#include <iomanip>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <variant>
#include <vector>

#include "engine/job/usage_error.hpp"
#include "engine/store/hdf5_file.hpp"
#include "engine/store/run_store.hpp"

namespace ggk::engine {

namespace {

double as_double(const TableValue& v) {
  if (const auto* d = std::get_if<double>(&v)) return *d;
  if (const auto* i = std::get_if<std::int32_t>(&v)) return *i;
  if (const auto* l = std::get_if<std::int64_t>(&v)) return static_cast<double>(*l);
  return std::nan("");
}

std::string as_text(const TableValue& v) {
  if (const auto* s = std::get_if<std::string>(&v)) return *s;
  std::ostringstream out;
  out << as_double(v);
  return out.str();
}

}  // namespace

namespace {

void print_info(const std::filesystem::path& path, std::ostream& out) {
  std::optional<Hdf5File> opened;
  try {
    opened.emplace(Hdf5File::open_read_only(path));
  } catch (const std::exception& e) {
    throw UsageError(e.what());
  }
  const Hdf5File& file = *opened;
  if (!file.has_attribute("/", "task") || !file.has_attribute("/", "job")) {
    throw UsageError(path.string() + " is not a ggk results file (no job or task attribute)");
  }
  const std::string task = file.read_string_attribute("/", "task");
  const auto runs = static_cast<std::int32_t>(file.read_int64_attribute("/", "runs"));
  const auto complete = static_cast<std::int32_t>(complete_runs(file, task, runs).size());
  out << "file:     " << path.string() << "\n"
      << "job file: " << file.read_string_attribute("/", "job_file") << "\n"
      << "task:     " << task << "\n"
      << "created:  " << file.read_string_attribute("/", "created") << " by ggk "
      << file.read_string_attribute("/", "ggk_version") << " ("
      << file.read_string_attribute("/", "git") << ")\n";
  if (file.has_attribute("/", "blas")) {
    out << "blas:     " << file.read_string_attribute("/", "blas") << "\n";
  }
  out << "runs:     " << complete << " of " << runs << " complete\n";
  const std::string summary = "/" + task + "/summary";
  if (!file.exists(summary)) {
    out << "summary:  not written yet (the sweep was interrupted; ggk run --resume finishes it)\n";
    return;
  }
  const std::vector<TableColumn> columns = file.read_table_columns(summary);
  const std::vector<TableRow> rows = file.read_table(summary);
  // Columns 2..7 identify the sweep point; metrics follow the status column.
  std::size_t first_metric = 0;
  for (std::size_t c = 0; c < columns.size(); ++c) {
    if (columns[c].name == "status") first_metric = c + 1;
  }
  struct Aggregate {
    std::vector<std::string> key;
    std::vector<double> sum;
    std::vector<int> count;
    int fits = 0, failed = 0;
  };
  std::map<std::int64_t, Aggregate> by_point;
  for (const TableRow& row : rows) {
    Aggregate& a = by_point[static_cast<std::int64_t>(as_double(row[1]))];
    if (a.key.empty()) {
      for (std::size_t c = 2; c + 1 < first_metric; ++c) a.key.push_back(as_text(row[c]));
      a.sum.assign(columns.size() - first_metric, 0.0);
      a.count.assign(columns.size() - first_metric, 0);
    }
    ++a.fits;
    const std::string status = as_text(row[first_metric - 1]);
    if (status == "invalid" || status == "solver_failed") ++a.failed;
    for (std::size_t c = first_metric; c < columns.size(); ++c) {
      const double v = as_double(row[c]);
      if (std::isfinite(v)) {
        a.sum[c - first_metric] += v;
        ++a.count[c - first_metric];
      }
    }
  }
  out << "summary:  " << rows.size() << " fits; mean over runs per sweep point\n";
  for (std::size_t c = 2; c + 1 < first_metric; ++c) out << std::setw(9) << columns[c].name;
  out << std::setw(7) << "fits" << std::setw(7) << "failed";
  for (std::size_t c = first_metric; c < columns.size(); ++c) {
    out << "  " << columns[c].name;
  }
  out << "\n";
  for (const auto& [point, a] : by_point) {
    for (const std::string& k : a.key) out << std::setw(9) << k;
    out << std::setw(7) << a.fits << std::setw(7) << a.failed;
    for (std::size_t m = 0; m < a.sum.size(); ++m) {
      const std::size_t width = columns[first_metric + m].name.size() + 2;
      out << std::setw(static_cast<int>(width)) << std::setprecision(4)
          << (a.count[m] > 0 ? a.sum[m] / a.count[m] : std::nan(""));
    }
    out << "\n";
  }
}

}  // namespace

void print_results_info(const std::filesystem::path& path, std::ostream& out) {
  // What is printed is gathered first: a file that fails half way (an attribute
  // of the wrong type, damage) prints one error, not half a report.
  std::ostringstream report;
  try {
    print_info(path, report);
  } catch (const UsageError&) {
    throw;
  } catch (const std::runtime_error& e) {
    throw UsageError(path.string() +
                     " does not read as a ggk results file (`ggk verify` says whether it is "
                     "damaged): " +
                     e.what());
  }
  out << report.str();
}

}  // namespace ggk::engine
