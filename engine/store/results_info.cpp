#include "engine/store/results_info.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <variant>
#include <vector>

#include "engine/hdf5/hdf5_file.hpp"
#include "engine/job/usage_error.hpp"
#include "engine/store/results_layout.hpp"
#include "engine/store/run_store.hpp"

namespace ggk::engine {

double student_t_975(std::int64_t dof) {
  // scipy.stats.t.ppf(0.975, dof) for 1..30 degrees of freedom.
  static constexpr std::array<double, 30> kTable = {
      12.706205, 4.302653, 3.182446, 2.776445, 2.570582, 2.446912, 2.364624, 2.306004,
      2.262157,  2.228139, 2.200985, 2.178813, 2.160369, 2.144787, 2.131450, 2.119905,
      2.109816,  2.100922, 2.093024, 2.085963, 2.079614, 2.073873, 2.068658, 2.063899,
      2.059539,  2.055529, 2.051831, 2.048407, 2.045230, 2.042272};
  if (dof < 1) return std::nan("");
  if (dof <= static_cast<std::int64_t>(kTable.size())) return kTable[dof - 1];
  // Beyond 30: the Cornish-Fisher expansion about the normal quantile (error
  // under 1e-6 there; Abramowitz & Stegun 26.7.5).
  const double z = 1.959963984540054;
  const double n = static_cast<double>(dof);
  const double z2 = z * z;
  const double g1 = (z2 + 1) * z / 4;
  const double g2 = ((5 * z2 + 16) * z2 + 3) * z / 96;
  const double g3 = (((3 * z2 + 19) * z2 + 17) * z2 - 15) * z / 384;
  const double g4 = ((((79 * z2 + 776) * z2 + 1482) * z2 - 1920) * z2 - 945) * z / 92160;
  return z + g1 / n + g2 / (n * n) + g3 / (n * n * n) + g4 / (n * n * n * n);
}

Interval mean_interval(std::span<const double> values) {
  double sum = 0.0;
  std::int64_t n = 0;
  for (const double v : values) {
    if (std::isfinite(v)) {
      sum += v;
      ++n;
    }
  }
  const double nan = std::nan("");
  if (n == 0) return {nan, nan, nan};
  const double mean = sum / static_cast<double>(n);
  if (n == 1) return {mean, nan, nan};
  double squares = 0.0;
  for (const double v : values) {
    if (std::isfinite(v)) squares += (v - mean) * (v - mean);
  }
  const double sd = std::sqrt(squares / static_cast<double>(n - 1));
  const double half = student_t_975(n - 1) * sd / std::sqrt(static_cast<double>(n));
  return {mean, mean - half, mean + half};
}

Interval wilson_interval(std::int64_t successes, std::int64_t trials) {
  const double nan = std::nan("");
  if (trials <= 0) return {nan, nan, nan};
  const double z = 1.959963984540054;
  const double n = static_cast<double>(trials);
  const double p = static_cast<double>(successes) / n;
  const double centre = (p + z * z / (2 * n)) / (1 + z * z / n);
  const double half = z / (1 + z * z / n) * std::sqrt(p * (1 - p) / n + z * z / (4 * n * n));
  // At 0 and 1 the bound is exactly 0 or 1 (not 1 - 1e-16 from rounding).
  return {p, successes == 0 ? 0.0 : std::max(0.0, centre - half),
          successes == trials ? 1.0 : std::min(1.0, centre + half)};
}

namespace {

double as_double(const TableValue& v) {
  if (const auto* d = std::get_if<double>(&v)) return *d;
  if (const auto* i = std::get_if<std::int32_t>(&v)) return *i;
  if (const auto* l = std::get_if<std::int64_t>(&v)) return static_cast<double>(*l);
  return std::nan("");
}

std::string number_text(double v, int precision = 4) {
  if (std::isnan(v)) return "nan";
  char text[64];
  std::snprintf(text, sizeof text, "%.*g", precision, v);
  return text;
}

// The shortest text that reads back as `v` (1e-06, not 9.9999999999999995e-07).
std::string exact_text(double v) {
  char text[64];
  const auto result = std::to_chars(text, text + sizeof text, v);
  return std::string(text, result.ptr);
}

std::string as_text(const TableValue& v) {
  if (const auto* s = std::get_if<std::string>(&v)) return *s;
  if (const auto* d = std::get_if<double>(&v)) return exact_text(*d);
  return std::to_string(static_cast<long long>(as_double(v)));
}

Interval clipped_to_rate(Interval ci) {
  if (!std::isnan(ci.low)) ci.low = std::clamp(ci.low, 0.0, 1.0);
  if (!std::isnan(ci.high)) ci.high = std::clamp(ci.high, 0.0, 1.0);
  return ci;
}

// A rate whose values at a point are all 0 or 1 is a per-run success (e.g.
// success from A): its interval is Wilson's; any other is a mean with Student's
// t (clipped to [0, 1] for a rate).
Interval metric_interval(const std::vector<double>& values, MetricKind kind) {
  if (kind == MetricKind::kRate) {
    // Wilson's for 0/1 values; Student's t clipped to [0, 1] for fractions.
    std::int64_t successes = 0, trials = 0;
    bool binary = true;
    for (const double v : values) {
      if (std::isnan(v)) continue;
      binary = binary && (v == 0.0 || v == 1.0);
      successes += v == 1.0 ? 1 : 0;
      ++trials;
    }
    if (binary && trials >= 1) return wilson_interval(successes, trials);
    return clipped_to_rate(mean_interval(values));
  }
  return mean_interval(values);
}

std::string csv_field(const std::string& text) {
  if (text.find_first_of(",\"\n") == std::string::npos) return text;
  std::string quoted = "\"";
  for (const char c : text) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

struct Point {
  std::vector<std::string> key;             // basis, kernels, sigma, solver, lambda
  std::vector<std::vector<double>> values;  // per metric, one value per fit
  int fits = 0, failed = 0, capped = 0;
};

void print_info(const std::filesystem::path& path, std::ostream& out, InfoFormat format,
                MetricKindLookup metric_kind) {
  std::optional<Hdf5File> opened;
  try {
    opened.emplace(Hdf5File::open_waiting_for_lock(path, true, std::chrono::seconds(10)));
  } catch (const std::exception& e) {
    throw UsageError(e.what());
  }
  const Hdf5File& file = *opened;
  ResultsHeader recorded;
  try {
    recorded = read_results_header(file);
  } catch (const ResultsHeaderError& e) {
    throw UsageError(e.what());
  }
  const std::string& task = recorded.task;
  const auto runs = static_cast<std::int32_t>(recorded.runs);
  const std::vector<std::int32_t> complete = complete_runs(file, task, runs);
  const bool text = format == InfoFormat::kText;
  if (text) {
    out << "file:     " << path.string() << "\n"
        << "job file: " << recorded.job_file << "\n"
        << "task:     " << task << "\n"
        << "created:  " << recorded.created << " by ggk " << recorded.ggk_version << " ("
        << recorded.git << ")\n";
    if (!recorded.blas.empty()) out << "blas:     " << recorded.blas << "\n";
    out << "runs:     " << complete.size() << " of " << runs << " complete\n";
  }
  // The rows of every complete run (what the summary holds once the job ends).
  std::vector<TableColumn> columns;
  std::vector<TableRow> rows;
  for (const std::int32_t run : complete) {
    const std::string table = run_group(task, run) + "/fit_metrics";
    if (columns.empty()) columns = file.read_table_columns(table);
    for (TableRow& row : file.read_table(table)) rows.push_back(std::move(row));
  }
  if (text && !file.exists("/" + task + "/summary") &&
      static_cast<std::int32_t>(complete.size()) < runs) {
    out << "summary:  not written yet (the sweep is running, or was interrupted: "
           "ggk run --resume finishes it)\n";
  }
  if (rows.empty()) return;
  // Columns: run, sweep_point, the point's axes up to status, then the metrics
  // (whatever the task reports) and fit_seconds.
  std::size_t status_column = 0;
  for (std::size_t c = 0; c < columns.size(); ++c) {
    if (columns[c].name == "status") status_column = c;
  }
  const std::size_t first_metric = status_column + 1;
  std::map<std::int64_t, Point> by_point;
  for (const TableRow& row : rows) {
    Point& p = by_point[static_cast<std::int64_t>(as_double(row[1]))];
    if (p.key.empty()) {
      for (std::size_t c = 2; c < status_column; ++c) p.key.push_back(as_text(row[c]));
      p.values.resize(columns.size() - first_metric);
    }
    ++p.fits;
    const std::optional<FitStatus> status = fit_status_from_text(as_text(row[status_column]));
    if (status && is_failed(*status)) ++p.failed;
    if (status == FitStatus::kMaxIterations) ++p.capped;
    for (std::size_t c = first_metric; c < columns.size(); ++c) {
      p.values[c - first_metric].push_back(as_double(row[c]));
    }
  }
  if (format == InfoFormat::kCsv) {
    for (std::size_t c = 2; c < status_column; ++c) out << csv_field(columns[c].name) << ",";
    out << "fits,failed,max_iterations";
    for (std::size_t c = first_metric; c < columns.size(); ++c) {
      const std::string& name = columns[c].name;
      out << "," << csv_field(name) << "," << csv_field(name + "_ci_low") << ","
          << csv_field(name + "_ci_high");
    }
    out << "\n";
    for (const auto& [index, p] : by_point) {
      for (const std::string& k : p.key) out << csv_field(k) << ",";
      out << p.fits << "," << p.failed << "," << p.capped;
      for (std::size_t m = 0; m < p.values.size(); ++m) {
        const Interval ci =
            metric_interval(p.values[m], metric_kind(task, columns[first_metric + m].name));
        out << "," << number_text(ci.estimate, 17) << "," << number_text(ci.low, 17) << ","
            << number_text(ci.high, 17);
      }
      out << "\n";
    }
    return;
  }
  int fits = 0, failed = 0, capped = 0;
  for (const auto& [index, p] : by_point) {
    fits += p.fits;
    failed += p.failed;
    capped += p.capped;
  }
  out << "summary:  " << fits << " fits (" << failed << " failed, " << capped
      << " stopped at max_iterations); per sweep point: mean over runs [95 % CI: Student t, "
         "Wilson for 0/1 metrics]\n";
  // A table of aligned cells: the header, then one line per sweep point.
  std::vector<std::vector<std::string>> cells;
  std::vector<std::string> header;
  for (std::size_t c = 2; c < status_column; ++c) header.push_back(columns[c].name);
  header.insert(header.end(), {"fits", "failed", "max_it"});
  for (std::size_t c = first_metric; c < columns.size(); ++c) header.push_back(columns[c].name);
  cells.push_back(header);
  for (const auto& [index, p] : by_point) {
    std::vector<std::string> line = p.key;
    line.insert(line.end(),
                {std::to_string(p.fits), std::to_string(p.failed), std::to_string(p.capped)});
    for (std::size_t m = 0; m < p.values.size(); ++m) {
      const Interval ci =
          metric_interval(p.values[m], metric_kind(task, columns[first_metric + m].name));
      line.push_back(std::isnan(ci.low) ? number_text(ci.estimate)
                                        : number_text(ci.estimate) + " [" + number_text(ci.low) +
                                              ", " + number_text(ci.high) + "]");
    }
    cells.push_back(line);
  }
  std::vector<std::size_t> widths(header.size(), 0);
  for (const auto& line : cells) {
    for (std::size_t i = 0; i < line.size(); ++i) widths[i] = std::max(widths[i], line[i].size());
  }
  for (const auto& line : cells) {
    for (std::size_t i = 0; i < line.size(); ++i) {
      out << (i == 0 ? "" : "  ") << std::string(widths[i] - line[i].size(), ' ') << line[i];
    }
    out << "\n";
  }
}

}  // namespace

void print_results_info(const std::filesystem::path& path, std::ostream& out, InfoFormat format,
                        MetricKindLookup metric_kind) {
  // What is printed is gathered first: a file that fails half way (an attribute
  // of the wrong type, damage) prints one error, not half a report.
  std::ostringstream report;
  try {
    print_info(path, report, format, metric_kind);
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
