#include "engine/store/results_info.hpp"

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <numeric>
#include <optional>
#include <sstream>
#include <string>
#include <variant>
#include <vector>

#include <boost/math/distributions/students_t.hpp>

#include "engine/hdf5/hdf5_file.hpp"
#include "engine/job/adaptive_rule.hpp"
#include "engine/job/job_error.hpp"
#include "engine/job/resolved_config.hpp"
#include "engine/job/usage_error.hpp"
#include "engine/store/adaptive_info.hpp"
#include "engine/store/adaptive_state.hpp"
#include "engine/store/one_line.hpp"
#include "engine/store/results_contents.hpp"
#include "engine/store/results_layout.hpp"
#include "engine/store/run_store.hpp"

namespace ggk::engine {

double student_t_975(std::int64_t dof) {
  if (dof < 1) return std::nan("");
  return boost::math::quantile(boost::math::students_t(static_cast<double>(dof)), 0.975);
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

std::string number_text(double v, int precision = 4) {
  if (std::isnan(v)) return "nan";
  char text[64];
  std::snprintf(text, sizeof text, "%.*g", precision, v);
  return text;
}

// The interval intersected with [low, high] (bounds that are NaN stay NaN).
Interval clipped_to(Interval ci, double low, double high) {
  if (!std::isnan(ci.low)) ci.low = std::clamp(ci.low, low, high);
  if (!std::isnan(ci.high)) ci.high = std::clamp(ci.high, low, high);
  return ci;
}

std::string csv_field(const std::string& text) {
  if (text.find_first_of(",\"\n") == std::string::npos) return text;
  std::string quoted = "\"";
  for (const char c : text) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

// Per sweep point: its axis values, counts and each metric's interval over runs.
struct PointSummary {
  std::vector<std::string> key;
  int fits = 0, failed = 0, capped = 0;
  std::vector<Interval> metrics;
};

Hdf5File open_for_reading(const std::filesystem::path& path) {
  try {
    return Hdf5File::open_waiting_for_lock(path, true, std::chrono::seconds(10));
  } catch (const std::exception& e) {
    throw UsageError(e.what());
  }
}

// The fits grouped by sweep point, in point order, with each metric's interval
// by its kind.
std::vector<PointSummary> summarise_points(const ResultsContents& contents) {
  struct Values {
    PointSummary summary;
    std::vector<std::vector<double>> per_metric;  // one value per fit
  };
  std::map<std::int64_t, Values> by_point;
  for (const FitRow& fit : contents.fits) {
    Values& point = by_point[fit.point];
    if (point.summary.key.empty()) {
      point.summary.key = fit.key;
      point.per_metric.resize(contents.metric_names.size());
    }
    ++point.summary.fits;
    if (fit.status && is_failed(*fit.status)) ++point.summary.failed;
    if (fit.status == FitStatus::kMaxIterations) ++point.summary.capped;
    for (std::size_t m = 0; m < point.per_metric.size(); ++m) {
      point.per_metric[m].push_back(fit.values[m]);
    }
  }
  std::vector<PointSummary> points;
  for (auto& [index, point] : by_point) {
    for (std::size_t m = 0; m < point.per_metric.size(); ++m) {
      point.summary.metrics.push_back(
          metric_interval(point.per_metric[m], contents.metric_specs[m]));
    }
    points.push_back(std::move(point.summary));
  }
  return points;
}

// One line per sweep point: its axes, the counts, and per metric the estimate
// and the interval's bounds to 17 digits (nothing for a file without fits).
void write_csv(const ResultsContents& contents, std::span<const PointSummary> points,
               std::ostream& out) {
  if (points.empty()) return;
  for (const std::string& axis : contents.axis_names) out << csv_field(axis) << ",";
  out << "fits,fits_failed,fits_capped";
  for (const std::string& name : contents.metric_names) {
    out << "," << csv_field(name) << "," << csv_field(name + "_ci_low") << ","
        << csv_field(name + "_ci_high");
  }
  out << "\n";
  for (const PointSummary& p : points) {
    for (const std::string& k : p.key) out << csv_field(k) << ",";
    out << p.fits << "," << p.failed << "," << p.capped;
    for (const Interval& ci : p.metrics) {
      out << "," << number_text(ci.estimate, 17) << "," << number_text(ci.low, 17) << ","
          << number_text(ci.high, 17);
    }
    out << "\n";
  }
}

// Lines of cells, right-aligned in columns two spaces apart.
// Left-aligned cells (a legend) end without trailing spaces.
enum class Align { kRight, kLeft };
void write_aligned(const std::vector<std::vector<std::string>>& cells, std::ostream& out,
                   Align align = Align::kRight) {
  std::vector<std::size_t> widths(cells.front().size(), 0);
  for (const auto& line : cells) {
    for (std::size_t i = 0; i < line.size(); ++i) widths[i] = std::max(widths[i], line[i].size());
  }
  for (const auto& line : cells) {
    std::string text;
    for (std::size_t i = 0; i < line.size(); ++i) {
      const std::string pad(widths[i] - line[i].size(), ' ');
      text += (i == 0 ? "" : "  ") + (align == Align::kRight ? pad + line[i] : line[i] + pad);
    }
    if (align == Align::kLeft) text.erase(text.find_last_not_of(' ') + 1);
    out << text << "\n";
  }
}

// "[0, 1]", "[0, inf)", "" for an unbounded range.
std::string range_text(const MetricSpec& spec) {
  const bool low = std::isfinite(spec.low), high = std::isfinite(spec.high);
  if (!low && !high) return "";
  return (low ? "[" + number_text(spec.low, 6) : "(-inf") + ", " +
         (high ? number_text(spec.high, 6) + "]" : "inf)");
}

// The interval method of a metric: what metric_interval does with it.
std::string interval_method(const MetricSpec& spec) {
  const bool bounded = std::isfinite(spec.low) || std::isfinite(spec.high);
  const std::string t = bounded ? "Student t within the range" : "Student t";
  return spec.kind == MetricKind::kIndicator ? "Wilson (0/1 per run), else " + t : t;
}

// One line per metric shown: its name, unit, range and interval, then what it
// measures (from the file's metric_specs; a file written before them says so).
void write_legend(const ResultsContents& contents, std::ostream& out) {
  out << "metrics:";
  if (!contents.metrics_declared) {
    out << "  (the file declares none: written by a ggk before 2026-11-29; kinds by name)";
  }
  out << "\n";
  std::vector<std::vector<std::string>> cells;
  for (const MetricSpec& spec : contents.metric_specs) {
    const std::string unit = spec.unit.empty() ? "" : "[" + spec.unit + "]";
    cells.push_back(
        {"  " + spec.name, unit, range_text(spec), interval_method(spec), one_line(spec.meaning)});
  }
  write_aligned(cells, out, Align::kLeft);
}

// The file's provenance and runs, then (when there are fits) the totals and a
// table of the sweep points, each metric as "mean [low, high]" to 4 digits.
void write_text(const std::filesystem::path& path, const ResultsContents& contents,
                std::span<const PointSummary> points, std::ostream& out) {
  const ResultsHeader& header = contents.header;
  out << "file:     " << path.string() << "\n"
      << "job file: " << one_line(header.job_file) << "\n"
      << "task:     " << one_line(header.task) << "\n"
      << "created:  " << one_line(header.created) << " by ggk " << one_line(header.ggk_version)
      << " (" << one_line(header.git) << ")\n";
  if (!header.blas.empty()) out << "blas:     " << one_line(header.blas) << "\n";
  const std::int64_t expected = header.runs * static_cast<std::int64_t>(contents.configurations);
  if (!header.job_overrides.empty() || !header.job_sweeps.empty()) {
    std::string words;
    const auto add = [&](const std::string& lines, const char* option) {
      std::istringstream in(lines);
      for (std::string line; std::getline(in, line);)
        words += std::string(" ") + option + " " + line;
    };
    add(header.job_overrides, "--set");
    add(header.job_sweeps, "--sweep");
    out << "options: " << one_line(words) << "\n";
  }
  if (contents.configurations > 1) {
    out << "study:    " << contents.configurations << " run configurations x " << header.runs
        << " runs\n";
    out << "runs:     " << contents.complete_runs << " of " << expected << " complete\n";
  } else {
    out << "runs:     " << contents.complete_runs << " of " << header.runs << " complete\n";
  }
  if (!contents.summary_written && static_cast<std::int64_t>(contents.complete_runs) < expected) {
    out << "summary:  not written yet (the sweep is running, or was interrupted: "
           "ggk run --resume finishes it)\n";
  }
  if (points.empty()) return;
  int fits = 0, failed = 0, capped = 0;
  for (const PointSummary& p : points) {
    fits += p.fits;
    failed += p.failed;
    capped += p.capped;
  }
  out << "summary:  " << fits << " fits (" << failed << " failed, " << capped
      << " capped: stopped at lspi.max_iterations); per sweep point: mean over runs [95 % CI]\n";
  write_legend(contents, out);
  std::vector<std::vector<std::string>> cells;
  std::vector<std::string> header_cells = contents.axis_names;
  header_cells.insert(header_cells.end(), {"fits", "failed", "capped"});
  header_cells.insert(header_cells.end(), contents.metric_names.begin(),
                      contents.metric_names.end());
  cells.push_back(std::move(header_cells));
  for (const PointSummary& p : points) {
    std::vector<std::string> line = p.key;
    line.insert(line.end(),
                {std::to_string(p.fits), std::to_string(p.failed), std::to_string(p.capped)});
    for (const Interval& ci : p.metrics) {
      line.push_back(std::isnan(ci.low) ? number_text(ci.estimate)
                                        : number_text(ci.estimate) + " [" + number_text(ci.low) +
                                              ", " + number_text(ci.high) + "]");
    }
    cells.push_back(std::move(line));
  }
  write_aligned(cells, out);
}

// Keeps the metrics named in `columns`, in that order (all when empty); a name
// that is no metric of the file is a UsageError listing the metrics.
void keep_columns(ResultsContents& contents, const std::vector<std::string>& columns) {
  if (columns.empty()) return;
  std::vector<std::size_t> kept;
  for (const std::string& name : columns) {
    const auto at = std::find(contents.metric_names.begin(), contents.metric_names.end(), name);
    if (at == contents.metric_names.end()) {
      std::string known;
      for (const std::string& metric : contents.metric_names) {
        known += (known.empty() ? "" : ", ") + metric;
      }
      throw UsageError("--columns: '" + one_line(name) + "' is no metric of the file (its " +
                       "metrics: " + (known.empty() ? "none yet" : known) + ")");
    }
    kept.push_back(static_cast<std::size_t>(at - contents.metric_names.begin()));
  }
  std::vector<std::string> names;
  std::vector<MetricSpec> specs;
  for (const std::size_t m : kept) {
    names.push_back(contents.metric_names[m]);
    specs.push_back(contents.metric_specs[m]);
  }
  contents.metric_names = std::move(names);
  contents.metric_specs = std::move(specs);
  for (FitRow& fit : contents.fits) {
    std::vector<double> values;
    for (const std::size_t m : kept) values.push_back(fit.values[m]);
    fit.values = std::move(values);
  }
}

// A metric's paired difference at one point of the other axes.
struct PairedMetric {
  double mean_a = 0.0, mean_b = 0.0;
  Interval difference;
  std::int64_t pairs = 0;
  const char* method = "t";
};

struct PairedPoint {
  std::vector<std::string> key;  // the other axes' values
  std::vector<PairedMetric> metrics;
};

// Per point of the axes other than `paired.axis` (in sweep order), each
// metric's a - b over the runs (and configurations) holding both sides with
// finite values: Newcombe's interval for a rate whose pairs are all 0 or 1,
// else the paired t (python/ggk_results/paired.py makes the same choice).
std::vector<PairedPoint> pair_points(const ResultsContents& contents,
                                     const PairedComparison& paired) {
  const auto axis_at =
      std::find(contents.axis_names.begin(), contents.axis_names.end(), paired.axis);
  if (axis_at == contents.axis_names.end()) {
    std::string axes;
    for (const std::string& axis : contents.axis_names) axes += (axes.empty() ? "" : ", ") + axis;
    throw UsageError("--paired: the file has no axis '" + one_line(paired.axis) +
                     "' (its axes: " + (axes.empty() ? "none yet" : axes) + ")");
  }
  const auto axis = static_cast<std::size_t>(axis_at - contents.axis_names.begin());
  PairedComparison sides = paired;
  std::vector<std::string> values;
  for (const FitRow& fit : contents.fits) {
    if (std::find(values.begin(), values.end(), fit.key[axis]) == values.end()) {
      values.push_back(fit.key[axis]);
    }
  }
  for (std::string* side : {&sides.a, &sides.b}) {
    const auto stored = std::find_if(values.begin(), values.end(), [&](const std::string& v) {
      return same_value_text(v, *side);
    });
    if (stored != values.end()) {
      *side = *stored;
    } else {
      std::string known;
      for (const std::string& value : values) known += (known.empty() ? "" : ", ") + value;
      throw UsageError("--paired: " + paired.axis + " has no value '" + one_line(*side) +
                       "' in the file (its values: " + (known.empty() ? "none yet" : known) + ")");
    }
  }
  // Per point of the other axes: run -> the fit of each side. The other axes'
  // values fix a study's run configuration, but for a run-level axis compared
  // (its two values are two configurations, whose run r share their seeds).
  struct Sides {
    std::vector<std::string> key;
    std::map<std::int64_t, std::pair<const FitRow*, const FitRow*>> runs;
  };
  std::vector<Sides> points;
  std::map<std::vector<std::string>, std::size_t> index_of;
  std::vector<const FitRow*> ordered;
  for (const FitRow& fit : contents.fits) ordered.push_back(&fit);
  std::stable_sort(ordered.begin(), ordered.end(),
                   [](const FitRow* x, const FitRow* y) { return x->point < y->point; });
  for (const FitRow* fit : ordered) {
    const bool is_a = fit->key[axis] == sides.a;
    if (!is_a && fit->key[axis] != sides.b) continue;
    std::vector<std::string> key = fit->key;
    key.erase(key.begin() + static_cast<std::ptrdiff_t>(axis));
    const auto [at, added] = index_of.emplace(key, points.size());
    if (added) points.push_back({key, {}});
    auto& slot = points[at->second].runs[fit->run];
    (is_a ? slot.first : slot.second) = fit;
  }
  std::vector<PairedPoint> result;
  for (const Sides& point : points) {
    PairedPoint out{point.key, {}};
    for (std::size_t m = 0; m < contents.metric_names.size(); ++m) {
      std::vector<double> a, b;
      for (const auto& entry : point.runs) {
        const FitRow* x = entry.second.first;
        const FitRow* y = entry.second.second;
        if (x == nullptr || y == nullptr) continue;
        if (std::isnan(x->values[m]) || std::isnan(y->values[m])) continue;
        a.push_back(x->values[m]);
        b.push_back(y->values[m]);
      }
      PairedMetric metric;
      metric.pairs = static_cast<std::int64_t>(a.size());
      const double nan = std::nan("");
      metric.mean_a =
          a.empty() ? nan
                    : std::accumulate(a.begin(), a.end(), 0.0) / static_cast<double>(a.size());
      metric.mean_b =
          b.empty() ? nan
                    : std::accumulate(b.begin(), b.end(), 0.0) / static_cast<double>(b.size());
      const auto binary = [](const std::vector<double>& v) {
        return std::all_of(v.begin(), v.end(), [](double x) { return x == 0.0 || x == 1.0; });
      };
      const MetricSpec& spec = contents.metric_specs[m];
      if (spec.kind == MetricKind::kIndicator && binary(a) && binary(b)) {
        metric.method = "newcombe";
        metric.difference = newcombe_paired_interval(a, b);
      } else {
        // A difference of two values in [low, high] lies in +-(high - low).
        const double width = spec.high - spec.low;
        metric.difference = clipped_to(paired_t_interval(a, b), -width, width);
      }
      out.metrics.push_back(metric);
    }
    result.push_back(std::move(out));
  }
  return result;
}

void write_paired_csv(const ResultsContents& contents, const PairedComparison& paired,
                      std::span<const PairedPoint> points, std::ostream& out) {
  if (points.empty()) return;
  const auto write_line = [&out](const std::vector<std::string>& fields) {
    for (std::size_t i = 0; i < fields.size(); ++i) out << (i == 0 ? "" : ",") << fields[i];
    out << "\n";
  };
  // <m>_a, <m>_b: the means of the two sides over the pairs (as paired()'s a, b).
  std::vector<std::string> header;
  for (const std::string& axis : contents.axis_names) {
    if (axis != paired.axis) header.push_back(csv_field(axis));
  }
  for (const std::string& name : contents.metric_names) {
    for (const char* suffix : {"_a", "_b", "_difference", "_ci_low", "_ci_high", "_pairs"}) {
      header.push_back(csv_field(name + suffix));
    }
  }
  write_line(header);
  for (const PairedPoint& p : points) {
    std::vector<std::string> fields;
    for (const std::string& k : p.key) fields.push_back(csv_field(k));
    for (const PairedMetric& m : p.metrics) {
      for (const double v :
           {m.mean_a, m.mean_b, m.difference.estimate, m.difference.low, m.difference.high}) {
        fields.push_back(number_text(v, 17));
      }
      fields.push_back(std::to_string(m.pairs));
    }
    write_line(fields);
  }
}

void write_paired_text(const std::filesystem::path& path, const ResultsContents& contents,
                       const PairedComparison& paired, std::span<const PairedPoint> points,
                       std::ostream& out) {
  out << "file:     " << path.string() << "\n"
      << "task:     " << one_line(contents.header.task) << "\n"
      << "paired:   " << paired.axis << " " << paired.a << " - " << paired.b
      << ", by run; per point of the other axes: mean difference [95 % CI: paired Student t, "
         "Newcombe for 0/1 rates] (pairs)\n";
  if (points.empty()) return;
  std::vector<std::vector<std::string>> cells;
  std::vector<std::string> header_cells;
  for (const std::string& axis : contents.axis_names) {
    if (axis != paired.axis) header_cells.push_back(axis);
  }
  header_cells.insert(header_cells.end(), contents.metric_names.begin(),
                      contents.metric_names.end());
  cells.push_back(std::move(header_cells));
  for (const PairedPoint& p : points) {
    std::vector<std::string> line = p.key;
    for (const PairedMetric& m : p.metrics) {
      const Interval& ci = m.difference;
      line.push_back((std::isnan(ci.low) ? number_text(ci.estimate)
                                         : number_text(ci.estimate) + " [" + number_text(ci.low) +
                                               ", " + number_text(ci.high) + "]") +
                     " (" + std::to_string(m.pairs) + ")");
    }
    cells.push_back(std::move(line));
  }
  write_aligned(cells, out);
}

void print_info(const std::filesystem::path& path, std::ostream& out, const InfoOptions& options) {
  const Hdf5File file = open_for_reading(path);
  ResultsContents contents = read_contents(file);
  // An adaptive study's cells, judged on every metric before --columns keeps some.
  std::optional<AdaptiveRule> rule;
  try {
    rule = adaptive_rule_of_text(contents.header.job, path.string() + " (its job)",
                                 static_cast<std::int32_t>(contents.header.runs));
  } catch (const JobError& e) {
    throw UsageError(std::string(e.what()));
  }
  if (options.adaptive && !rule) {
    throw UsageError("--adaptive: " + path.string() +
                     " is no adaptive study (its job has no [adaptive] table)");
  }
  std::optional<AdaptiveState> state;
  if (rule) {
    state = adaptive_state(contents, *rule, static_cast<std::int32_t>(contents.configurations),
                           static_cast<std::int32_t>(contents.header.runs),
                           adaptive_scope_of(contents.header));
  }
  if (options.adaptive) {
    const auto rows = adaptive_cell_rows(*state, *rule, options.format == InfoFormat::kCsv);
    if (options.format == InfoFormat::kCsv) {
      for (const auto& row : rows) {
        for (std::size_t i = 0; i < row.size(); ++i)
          out << (i == 0 ? "" : ",") << csv_field(row[i]);
        out << "\n";
      }
    } else {
      out << "file:     " << path.string() << "\n"
          << "adaptive: "
          << adaptive_status_line(*state, *rule, static_cast<std::int32_t>(contents.header.runs))
          << "\n";
      write_aligned(rows, out);
    }
    return;
  }
  keep_columns(contents, options.columns);
  if (options.paired) {
    const std::vector<PairedPoint> points = pair_points(contents, *options.paired);
    if (options.format == InfoFormat::kCsv) {
      write_paired_csv(contents, *options.paired, points, out);
    } else {
      write_paired_text(path, contents, *options.paired, points, out);
    }
    return;
  }
  const std::vector<PointSummary> points = summarise_points(contents);
  if (options.format == InfoFormat::kCsv) {
    write_csv(contents, points, out);
  } else {
    write_text(path, contents, points, out);
    if (state) {
      out << "adaptive: "
          << adaptive_status_line(*state, *rule, static_cast<std::int32_t>(contents.header.runs))
          << "\n";
      write_aligned(adaptive_cell_rows(*state, *rule, false), out);
    }
  }
}

}  // namespace

Interval metric_interval(std::span<const double> values, const MetricSpec& spec) {
  if (spec.kind == MetricKind::kIndicator) {
    // Wilson's for 0/1 values (inside [0, 1] already); else as a mean.
    std::int64_t successes = 0, trials = 0;
    bool binary = true;
    for (const double v : values) {
      if (std::isnan(v)) continue;
      binary = binary && (v == 0.0 || v == 1.0);
      successes += v == 1.0 ? 1 : 0;
      ++trials;
    }
    if (binary && trials >= 1) return wilson_interval(successes, trials);
  }
  return clipped_to(mean_interval(values), spec.low, spec.high);
}

Interval paired_t_interval(std::span<const double> a, std::span<const double> b) {
  std::vector<double> differences;
  for (std::size_t i = 0; i < a.size() && i < b.size(); ++i) {
    if (!std::isnan(a[i]) && !std::isnan(b[i])) differences.push_back(a[i] - b[i]);
  }
  return mean_interval(differences);  // ttest_rel's interval is the differences' t interval
}

Interval newcombe_paired_interval(std::span<const double> a, std::span<const double> b) {
  const double nan = std::nan("");
  const std::size_t size = std::min(a.size(), b.size());
  if (size == 0) return {nan, nan, nan};
  std::int64_t both = 0, only_a = 0, only_b = 0;
  for (std::size_t i = 0; i < size; ++i) {
    both += a[i] == 1.0 && b[i] == 1.0 ? 1 : 0;
    only_a += a[i] == 1.0 && b[i] != 1.0 ? 1 : 0;
    only_b += a[i] != 1.0 && b[i] == 1.0 ? 1 : 0;
  }
  const auto n = static_cast<std::int64_t>(size);
  const std::int64_t neither = n - both - only_a - only_b;
  const Interval r1 = wilson_interval(both + only_a, n);
  const Interval r2 = wilson_interval(both + only_b, n);
  // phi: the correlation of the pairs' outcomes, 0 when a margin is empty;
  // a positive product difference shrunk by n / 2 (Newcombe's continuity).
  const double margins = static_cast<double>(both + only_a) *
                         static_cast<double>(only_b + neither) *
                         static_cast<double>(both + only_b) * static_cast<double>(only_a + neither);
  double phi = 0.0;
  if (margins > 0) {
    const double product = static_cast<double>(both) * static_cast<double>(neither) -
                           static_cast<double>(only_a) * static_cast<double>(only_b);
    const double corrected =
        product > 0 ? std::max(product - static_cast<double>(n) / 2, 0.0) : product;
    phi = corrected / std::sqrt(margins);
  }
  const double p1 = r1.estimate, p2 = r2.estimate;
  const double d = p1 - p2;
  const double low_spread = (p1 - r1.low) * (p1 - r1.low) -
                            2 * phi * (p1 - r1.low) * (r2.high - p2) +
                            (r2.high - p2) * (r2.high - p2);
  const double high_spread = (p2 - r2.low) * (p2 - r2.low) -
                             2 * phi * (p2 - r2.low) * (r1.high - p1) +
                             (r1.high - p1) * (r1.high - p1);
  return {d, std::max(-1.0, d - std::sqrt(std::max(0.0, low_spread))),
          std::min(1.0, d + std::sqrt(std::max(0.0, high_spread)))};
}

PairedComparison parse_paired_option(std::string_view text) {
  const std::size_t equals = text.find('=');
  const std::size_t comma = text.find(',', equals == std::string_view::npos ? 0 : equals);
  if (equals == std::string_view::npos || equals == 0 || comma == std::string_view::npos ||
      comma == equals + 1 || comma + 1 == text.size() ||
      text.find(',', comma + 1) != std::string_view::npos) {
    throw UsageError("--paired '" + one_line(std::string(text)) +
                     "': write AXIS=A,B, e.g. --paired basis=ggk,ogk");
  }
  return {std::string(text.substr(0, equals)),
          std::string(text.substr(equals + 1, comma - equals - 1)),
          std::string(text.substr(comma + 1))};
}

std::vector<std::string> info_column_list(std::string_view text) {
  std::vector<std::string> names;
  if (text.empty()) return names;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = text.find(',', start);
    const std::string_view name = text.substr(
        start, comma == std::string_view::npos ? std::string_view::npos : comma - start);
    if (name.empty()) {
      throw UsageError("--columns '" + one_line(std::string(text)) +
                       "': an empty name (write a,b,c)");
    }
    names.emplace_back(name);
    if (comma == std::string_view::npos) return names;
    start = comma + 1;
  }
}

void print_results_info(const std::filesystem::path& path, std::ostream& out, InfoFormat format) {
  InfoOptions options;
  options.format = format;
  print_results_info(path, out, options);
}

void print_results_info(const std::filesystem::path& path, std::ostream& out,
                        const InfoOptions& options) {
  // What is printed is gathered first: a file that fails half way (an attribute
  // of the wrong type, damage) prints one error, not half a report.
  std::ostringstream report;
  try {
    print_info(path, report, options);
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
