#include "engine/store/adaptive_state.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <iterator>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "engine/job/resolved_config.hpp"
#include "engine/job/usage_error.hpp"
#include "kernels/confidence_sequence.hpp"

namespace ggk::engine {
namespace {

using RunFits = std::map<std::int64_t, const FitRow*>;  // run -> fit

// One point of the other axes of a comparison: its two sides' sweep points
// ((configuration << 32) + index, FitRow::point; -1: none) and their fits by run.
struct Pairing {
  std::vector<std::string> key;
  std::int64_t first_point = 0;  // side A's point: the cells' order
  std::int32_t configuration_a = -1;
  std::int32_t configuration_b = -1;
  std::int64_t point_a = -1;
  std::int64_t point_b = -1;
  const RunFits* a = nullptr;  // set by attach_fits
  const RunFits* b = nullptr;
};

// The pairings of `compare` over the sweep points `rows` lists (a file's fits,
// or a study's planned rows: run/adaptive_shards.hpp), in side A's point order.
std::vector<Pairing> pairings(const ResultsContents& rows, const AdaptiveComparison& compare,
                              std::vector<std::string>& key_names) {
  const auto axis_at = std::find(rows.axis_names.begin(), rows.axis_names.end(), compare.axis);
  if (axis_at == rows.axis_names.end()) {
    throw UsageError("[adaptive] compare = \"" + compare.text() + "\": the results have no axis '" +
                     compare.axis + "'");
  }
  const auto axis = static_cast<std::size_t>(axis_at - rows.axis_names.begin());
  key_names = rows.axis_names;
  key_names.erase(key_names.begin() + static_cast<std::ptrdiff_t>(axis));
  std::vector<Pairing> result;
  std::map<std::vector<std::string>, std::size_t> index_of;
  for (const FitRow& fit : rows.fits) {
    const bool is_a = same_value_text(fit.key[axis], compare.a);
    if (!is_a && !same_value_text(fit.key[axis], compare.b)) continue;
    std::vector<std::string> key = fit.key;
    key.erase(key.begin() + static_cast<std::ptrdiff_t>(axis));
    const auto [at, added] = index_of.emplace(key, result.size());
    if (added) {
      Pairing pairing;
      pairing.key = std::move(key);
      pairing.first_point = INT64_MAX;
      result.push_back(std::move(pairing));
    }
    Pairing& pairing = result[at->second];
    if (is_a) {
      pairing.configuration_a = fit.configuration;
      pairing.point_a = fit.point;
      pairing.first_point = std::min(pairing.first_point, fit.point);
    } else {
      pairing.configuration_b = fit.configuration;
      pairing.point_b = fit.point;
    }
  }
  std::stable_sort(result.begin(), result.end(), [](const Pairing& x, const Pairing& y) {
    return x.first_point < y.first_point;
  });
  return result;
}

// Points each pairing's sides at their fits in `by_point` (point -> run -> fit).
void attach_fits(std::vector<Pairing>& pairings, const std::map<std::int64_t, RunFits>& by_point) {
  static const RunFits kNone;
  for (Pairing& pairing : pairings) {
    const auto a = by_point.find(pairing.point_a);
    const auto b = by_point.find(pairing.point_b);
    pairing.a = a == by_point.end() ? &kNone : &a->second;
    pairing.b = b == by_point.end() ? &kNone : &b->second;
  }
}

// A point's index among its configuration's sweep points (expand_points).
std::int32_t point_index(std::int64_t point) {
  return static_cast<std::int32_t>(point & 0xffffffff);
}

// A fit's configuration and axis values, numbers as their value ("8" and "8.0"
// alike): a sweep point whatever index a file gave it (a study grown by
// fit-level values renumbers a run's points only when it extends the run).
std::vector<std::string> point_identity(const FitRow& fit) {
  std::vector<std::string> identity = {std::to_string(fit.configuration)};
  for (const std::string& cell : fit.key) {
    char* end = nullptr;
    const double value = std::strtod(cell.c_str(), &end);
    const bool number = !cell.empty() && *end == '\0';
    identity.push_back(number ? canonical_number(value) : cell);
  }
  return identity;
}

std::string metric_list(const std::vector<std::string>& names) {
  std::string text;
  for (const std::string& name : names) {
    if (name != "fit_seconds") text += (text.empty() ? "" : ", ") + name;
  }
  return text;
}

}  // namespace

std::string_view cell_state_name(CellState state) {
  switch (state) {
    case CellState::kPositive:
      return "+";
    case CellState::kNegative:
      return "-";
    case CellState::kNarrow:
      return "narrow";
    case CellState::kOpen:
      return "open";
    case CellState::kCapped:
      return "capped";
    case CellState::kFailed:
      return "failed";
  }
  return "?";
}

std::int64_t AdaptiveState::open_cells() const {
  return std::count_if(cells.begin(), cells.end(),
                       [](const AdaptiveCell& cell) { return cell.state == CellState::kOpen; });
}

std::optional<MetricRange> metric_range(const AdaptiveRule& rule, std::string_view metric,
                                        MetricKind kind) {
  if (std::optional<MetricRange> declared = rule.declared_range(metric)) return declared;
  if (kind == MetricKind::kIndicator || kind == MetricKind::kFraction) {
    return MetricRange{std::string(metric), 0.0, 1.0};
  }
  return std::nullopt;
}

namespace {

// A compared metric: its column in the contents' metrics and its range.
struct ComparedMetric {
  std::size_t column = 0;
  MetricRange range;
};

// The rule's metrics as columns with ranges; a metric the task does not report,
// or one with no known range under a method that needs one, is a UsageError.
std::vector<ComparedMetric> compared_metrics(const ResultsContents& contents,
                                             const AdaptiveRule& rule) {
  std::vector<ComparedMetric> compared;
  for (const std::string& metric : rule.metrics) {
    const auto at = std::find(contents.metric_names.begin(), contents.metric_names.end(), metric);
    if (at == contents.metric_names.end() || metric == "fit_seconds") {
      throw UsageError("[adaptive] metrics: the task reports no metric '" + metric +
                       "' (its metrics: " + metric_list(contents.metric_names) + ")");
    }
    const MetricKind kind =
        contents.metric_specs[static_cast<std::size_t>(at - contents.metric_names.begin())].kind;
    std::optional<MetricRange> range = metric_range(rule, metric, kind);
    if (!range && rule.method == AdaptiveMethod::kAsymptotic) {  // any value goes
      range = MetricRange{metric, -std::numeric_limits<double>::infinity(),
                          std::numeric_limits<double>::infinity()};
    }
    if (!range) {
      throw UsageError("[adaptive] metrics: '" + metric +
                       "' is no rate or fraction, so its range is unknown: give it as "
                       "[adaptive.range] " +
                       metric +
                       " = [LOW, HIGH] (or method = "
                       "\"asymptotic\", which needs none)");
    }
    compared.push_back({static_cast<std::size_t>(at - contents.metric_names.begin()), *range});
  }
  return compared;
}

// One cell (a pairing's metric) judged on the paired runs, computed so far, of
// the runs the current look gives both its configurations (state.runs_wanted):
// their differences' mean and confidence sequence at state.cell_level, and
// whether the rule's target is met (+, -, narrow), still open, or failed (a NaN).
// The caller sets `comparison` and the capped state. A value outside the
// metric's range is a UsageError.
AdaptiveCell judge_cell(const ResultsContents& contents, const AdaptiveRule& rule,
                        const AdaptiveState& state, const Pairing& pairing,
                        const ComparedMetric& metric, std::int32_t max_runs) {
  AdaptiveCell cell;
  cell.key = pairing.key;
  cell.metric = contents.metric_names[metric.column];
  cell.configuration_a = pairing.configuration_a;
  cell.configuration_b = pairing.configuration_b;
  std::int64_t n = 0;
  if (cell.configuration_a >= 0 && cell.configuration_b >= 0) {
    n = std::min(state.runs_wanted[static_cast<std::size_t>(cell.configuration_a)],
                 state.runs_wanted[static_cast<std::size_t>(cell.configuration_b)]);
  }
  std::vector<double> differences;
  bool failed = false;
  for (std::int64_t r = 0; r < n; ++r) {
    const auto a = pairing.a->find(r);
    const auto b = pairing.b->find(r);
    if (a == pairing.a->end() || b == pairing.b->end()) break;  // not yet computed
    const double x = a->second->values[metric.column];
    const double y = b->second->values[metric.column];
    if (std::isnan(x) || std::isnan(y)) {
      failed = true;
      break;
    }
    for (const double v : {x, y}) {
      if (!(v >= metric.range.low && v <= metric.range.high)) {
        throw UsageError("[adaptive] range: " + cell.metric + " = " + as_text(TableValue{v}) +
                         " in run " + std::to_string(r) + " lies outside its range [" +
                         as_text(TableValue{metric.range.low}) + ", " +
                         as_text(TableValue{metric.range.high}) +
                         "]: the range must hold every value (give the one the task's physics "
                         "bounds it by)");
      }
    }
    differences.push_back(x - y);
  }
  cell.runs = static_cast<std::int64_t>(differences.size());
  const double width = metric.range.high - metric.range.low;
  if (failed) {
    cell.state = CellState::kFailed;
  } else if (differences.empty()) {
    cell.mean = cell.lower = cell.upper = std::nan("");
  } else {
    double sum = 0.0;
    for (const double d : differences) sum += d;
    cell.mean = sum / static_cast<double>(differences.size());
    const kernels::ConfidenceSequence sequence =
        rule.method == AdaptiveMethod::kBernstein
            ? kernels::confidence_sequence(differences, -width, width, state.cell_level)
            : kernels::asymptotic_confidence_sequence(differences, state.cell_level, max_runs);
    cell.lower = sequence.lower.back();
    cell.upper = sequence.upper.back();
    if (rule.target == AdaptiveTarget::kSign && cell.lower > 0.0) {
      cell.state = CellState::kPositive;
    } else if (rule.target == AdaptiveTarget::kSign && cell.upper < 0.0) {
      cell.state = CellState::kNegative;
    } else if (rule.target == AdaptiveTarget::kWidth && cell.upper - cell.lower < rule.width) {
      cell.state = CellState::kNarrow;
    }
  }
  return cell;
}

}  // namespace

AdaptiveState adaptive_state(const ResultsContents& contents, const AdaptiveRule& rule,
                             std::int32_t configurations, std::int32_t max_runs,
                             const AdaptiveScope& scope, const ResultsContents* planned) {
  AdaptiveState state;
  const auto count = static_cast<std::size_t>(configurations);
  // The configurations this process judges (a shard's, or all).
  std::vector<bool> judged(count, scope.configurations.empty());
  for (const std::int32_t c : scope.configurations) {
    if (c < 0 || c >= configurations) {
      throw UsageError("an adaptive study's shard names run configuration " + std::to_string(c) +
                       " (configurations_selected), which its study of " +
                       std::to_string(configurations) + " configurations lacks");
    }
    judged[static_cast<std::size_t>(c)] = true;
  }
  state.runs_wanted.assign(count, 0);
  for (std::size_t c = 0; c < count; ++c) {
    if (judged[c]) state.runs_wanted[c] = std::min(rule.batch, max_runs);
  }
  state.configurations_judged = std::count(judged.begin(), judged.end(), true);
  state.level_cells = scope.cells.value_or(0);
  state.key_names.resize(rule.comparisons.size());

  // Every configuration's sweep points, and those each stored run holds.
  const ResultsContents& rows = planned != nullptr ? *planned : contents;
  std::vector<std::vector<std::int32_t>> all_points(count);
  for (const FitRow& fit : rows.fits) {
    if (fit.configuration >= 0 && fit.configuration < configurations) {
      all_points[static_cast<std::size_t>(fit.configuration)].push_back(point_index(fit.point));
    }
  }
  for (std::vector<std::int32_t>& points : all_points) {
    std::sort(points.begin(), points.end());
    points.erase(std::unique(points.begin(), points.end()), points.end());
  }
  state.run_points.resize(count);
  for (std::size_t c = 0; c < count; ++c) state.run_points[c].push_back({0, all_points[c]});
  // The file's fits by point, a planned study's points found by their values.
  std::map<std::vector<std::string>, std::int64_t> planned_point;
  if (planned != nullptr) {
    for (const FitRow& fit : planned->fits) planned_point.emplace(point_identity(fit), fit.point);
  }
  std::vector<std::map<std::int64_t, std::set<std::int32_t>>> stored(count);  // run -> points
  // Per configuration, the stored runs whose fits carry another index than the
  // study's (a study grown by fit-level values): extended, if by nothing.
  std::vector<std::set<std::int64_t>> renumbered(count);
  std::map<std::int64_t, RunFits> by_point;
  for (const FitRow& fit : contents.fits) {
    std::int64_t point = fit.point;
    if (planned != nullptr) {
      const auto at = planned_point.find(point_identity(fit));
      if (at == planned_point.end()) continue;  // no point of the study (never judged)
      point = at->second;
      if (point != fit.point && fit.configuration >= 0 && fit.configuration < configurations) {
        renumbered[static_cast<std::size_t>(fit.configuration)].insert(fit.run);
      }
    }
    by_point[point][fit.run] = &fit;
    if (fit.configuration >= 0 && fit.configuration < configurations) {
      stored[static_cast<std::size_t>(fit.configuration)][fit.run].insert(point_index(point));
    }
  }
  const auto needed_of = [&](std::size_t c, std::int64_t run) -> const std::vector<std::int32_t>& {
    const std::vector<RunPoints>& segments = state.run_points[c];
    auto at = segments.end();
    while (at != segments.begin() && std::prev(at)->first_run > run) --at;
    return std::prev(at)->points;
  };
  // The points run `run` of configuration c needs and lacks; nullopt: no such run.
  const auto lacking_of = [&](std::size_t c,
                              std::int64_t run) -> std::optional<std::vector<std::int32_t>> {
    const auto held = stored[c].find(run);
    if (held == stored[c].end()) return std::nullopt;
    std::vector<std::int32_t> lacking;
    for (const std::int32_t p : needed_of(c, run)) {
      if (held->second.count(p) == 0) lacking.push_back(p);
    }
    return lacking;
  };
  // The current look's runs still to compute, and its fits counted.
  const auto fill_needs = [&] {
    state.needs.clear();
    state.fits_wanted = state.fits_whole = 0;
    for (std::size_t c = 0; c < count; ++c) {
      if (!judged[c]) continue;
      for (std::int32_t run = 0; run < state.runs_wanted[c]; ++run) {
        const std::vector<std::int32_t>& needed = needed_of(c, run);
        state.fits_wanted += static_cast<std::int64_t>(needed.size());
        state.fits_whole += static_cast<std::int64_t>(all_points[c].size());
        std::optional<std::vector<std::int32_t>> lacking = lacking_of(c, run);
        if (!lacking) {
          state.needs.push_back({static_cast<std::int32_t>(c), run, true,
                                 needed == all_points[c] ? std::vector<std::int32_t>{} : needed});
        } else if (!lacking->empty() || renumbered[c].count(run) > 0) {
          state.needs.push_back({static_cast<std::int32_t>(c), run, false, std::move(*lacking)});
        }
      }
    }
  };
  if (contents.fits.empty()) {  // look 1 has no runs yet
    fill_needs();
    return state;
  }

  const std::vector<ComparedMetric> compared = compared_metrics(contents, rule);

  // Per comparison, its points of the other axes; each is one cell per metric.
  std::vector<std::vector<Pairing>> points;
  std::size_t cell_count = 0;
  // Per sweep point, the first cells of the pairings it is a side of.
  std::map<std::int64_t, std::vector<std::size_t>> cells_of_point;
  for (std::size_t c = 0; c < rule.comparisons.size(); ++c) {
    points.push_back(pairings(rows, rule.comparisons[c], state.key_names[c]));
    attach_fits(points.back(), by_point);
    for (const Pairing& pairing : points.back()) {
      for (const std::int64_t point : {pairing.point_a, pairing.point_b}) {
        if (point >= 0) cells_of_point[point].push_back(cell_count);
      }
      cell_count += compared.size();
    }
  }
  if (scope.cells && static_cast<std::int64_t>(cell_count) > *scope.cells) {
    throw std::logic_error("adaptive_state: the file holds " + std::to_string(cell_count) +
                           " cells, more than the study's " + std::to_string(*scope.cells));
  }
  state.level_cells = scope.cells ? *scope.cells : static_cast<std::int64_t>(cell_count);
  const double alpha = 1.0 - rule.level;
  state.cell_level = rule.correction == AdaptiveCorrection::kBonferroni && state.level_cells > 0
                         ? 1.0 - alpha / static_cast<double>(state.level_cells)
                         : rule.level;

  // Whether a configuration holds runs 0 .. runs - 1, each with the points it needs.
  const auto holds = [&](std::size_t configuration, std::int32_t runs) {
    for (std::int32_t r = 0; r < runs; ++r) {
      const std::optional<std::vector<std::int32_t>> lacking = lacking_of(configuration, r);
      if (!lacking || !lacking->empty()) return false;
    }
    return true;
  };
  // The points a configuration's next runs need after a complete look: a point
  // stays while a cell it is a side of is open (or it is in no cell).
  const auto needed_after_look = [&](std::size_t configuration) {
    std::vector<std::int32_t> needed;
    for (const std::int32_t p : all_points[configuration]) {
      const auto at = cells_of_point.find((static_cast<std::int64_t>(configuration) << 32) + p);
      bool open = at == cells_of_point.end();
      for (std::size_t i = 0; !open && i < at->second.size(); ++i) {
        for (std::size_t m = 0; m < compared.size(); ++m) {
          if (state.cells[at->second[i] + m].state == CellState::kOpen) open = true;
        }
      }
      if (open) needed.push_back(p);
    }
    return needed;
  };

  // Judges every cell on the runs the current look gives its configurations. A
  // cell decided at a complete look stays as it was then (the rule stopped it).
  std::vector<std::optional<AdaptiveCell>> decided(cell_count);
  const auto judge = [&](bool complete) {
    state.cells.clear();
    for (std::size_t c = 0; c < points.size(); ++c) {
      for (const Pairing& pairing : points[c]) {
        for (const ComparedMetric& metric : compared) {
          if (const std::optional<AdaptiveCell>& earlier = decided[state.cells.size()]) {
            state.cells.push_back(*earlier);
            continue;
          }
          AdaptiveCell cell = judge_cell(contents, rule, state, pairing, metric, max_runs);
          cell.comparison = c;
          if (cell.state == CellState::kOpen && complete && cell.runs >= max_runs) {
            cell.state = CellState::kCapped;
          }
          const bool stops = cell.state == CellState::kPositive ||
                             cell.state == CellState::kNegative || cell.state == CellState::kNarrow;
          if (complete && stops) decided[state.cells.size()] = cell;
          state.cells.push_back(std::move(cell));
        }
      }
    }
  };

  for (;;) {
    bool complete = true;
    for (std::size_t c = 0; c < count; ++c) {
      if (judged[c] && !holds(c, state.runs_wanted[c])) complete = false;
    }
    judge(complete);
    if (!complete) break;  // the look's runs are being computed
    std::vector<std::int32_t> next = state.runs_wanted;
    for (const AdaptiveCell& cell : state.cells) {
      if (cell.state != CellState::kOpen) continue;
      const auto asked =
          static_cast<std::int32_t>(std::min<std::int64_t>(cell.runs + rule.batch, max_runs));
      for (const std::int32_t c : {cell.configuration_a, cell.configuration_b}) {
        if (c >= 0)
          next[static_cast<std::size_t>(c)] = std::max(next[static_cast<std::size_t>(c)], asked);
      }
    }
    if (next == state.runs_wanted) {
      state.done = true;
      break;
    }
    // The runs the next look adds hold the points their open cells need.
    for (std::size_t c = 0; c < count; ++c) {
      if (next[c] == state.runs_wanted[c]) continue;
      std::vector<std::int32_t> needed = needed_after_look(c);
      if (needed != state.run_points[c].back().points) {
        state.run_points[c].push_back({state.runs_wanted[c], std::move(needed)});
      }
    }
    state.runs_wanted = std::move(next);
    ++state.looks;
  }
  fill_needs();
  return state;
}

AdaptiveScope adaptive_scope_of(const ResultsHeader& header) {
  AdaptiveScope scope;
  if (!header.configurations_selected) return scope;
  for (const std::int64_t c : header.configurations_selected->configurations) {
    scope.configurations.push_back(static_cast<std::int32_t>(c));
  }
  scope.cells = header.configurations_selected->cells;
  return scope;
}

AdaptivePlan adaptive_plan(const ResultsContents& planned, const AdaptiveRule& rule,
                           std::int32_t configurations) {
  // Union-find over the configurations: a pairing links its two sides'.
  std::vector<std::int32_t> parent(static_cast<std::size_t>(configurations));
  for (std::int32_t c = 0; c < configurations; ++c) parent[static_cast<std::size_t>(c)] = c;
  const auto root = [&](std::int32_t c) {
    while (parent[static_cast<std::size_t>(c)] != c) c = parent[static_cast<std::size_t>(c)];
    return c;
  };
  AdaptivePlan plan;
  for (const AdaptiveComparison& comparison : rule.comparisons) {
    std::vector<std::string> key_names;
    for (const Pairing& pairing : pairings(planned, comparison, key_names)) {
      plan.cells += static_cast<std::int64_t>(rule.metrics.size());
      if (pairing.configuration_a < 0 || pairing.configuration_b < 0) continue;
      const std::int32_t a = root(pairing.configuration_a);
      const std::int32_t b = root(pairing.configuration_b);
      parent[static_cast<std::size_t>(std::max(a, b))] = std::min(a, b);  // the first stays root
    }
  }
  plan.group_of.assign(static_cast<std::size_t>(configurations), -1);
  std::vector<std::int32_t> group_of_root(static_cast<std::size_t>(configurations), -1);
  for (std::int32_t c = 0; c < configurations; ++c) {
    std::int32_t& group = group_of_root[static_cast<std::size_t>(root(c))];
    if (group < 0) group = plan.groups++;
    plan.group_of[static_cast<std::size_t>(c)] = group;
  }
  return plan;
}

}  // namespace ggk::engine
