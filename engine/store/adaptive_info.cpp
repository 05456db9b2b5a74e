#include "engine/store/adaptive_info.hpp"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

namespace ggk::engine {
namespace {

std::string number(double v, bool exact) {
  if (std::isnan(v)) return "nan";
  char text[64];
  if (exact) {
    const auto result = std::to_chars(text, text + sizeof text, v);
    return std::string(text, result.ptr);
  }
  std::snprintf(text, sizeof text, "%.4g", v);
  return text;
}

}  // namespace

std::string adaptive_status_line(const AdaptiveState& state, const AdaptiveRule& rule,
                                 std::int32_t max_runs) {
  std::map<CellState, std::int64_t> count;
  for (const AdaptiveCell& cell : state.cells) ++count[cell.state];
  const std::int64_t decided =
      count[CellState::kPositive] + count[CellState::kNegative] + count[CellState::kNarrow];
  std::string line = "look " + std::to_string(state.looks) + (state.done ? ", done" : ", running") +
                     ": " + std::to_string(decided) + " of " + std::to_string(state.cells.size()) +
                     " cells decided";
  if (rule.target == AdaptiveTarget::kSign) {
    line += " (+ " + std::to_string(count[CellState::kPositive]) + ", - " +
            std::to_string(count[CellState::kNegative]) + ")";
  } else {
    line += " (narrower than " + number(rule.width, false) + ")";
  }
  line += ", " + std::to_string(count[CellState::kOpen]) + " open, " +
          std::to_string(count[CellState::kCapped]) + " capped";
  if (count[CellState::kFailed] > 0) {
    line += ", " + std::to_string(count[CellState::kFailed]) + " with failed fits";
  }
  std::string runs;
  std::int64_t total = 0;
  for (const std::int32_t wanted : state.runs_wanted) {
    runs += (runs.empty() ? "" : ", ") + std::to_string(wanted);
    total += wanted;
  }
  const auto configurations = static_cast<std::int64_t>(state.runs_wanted.size());
  line += "; runs per configuration " + runs + " (" + std::to_string(total) + " of at most " +
          std::to_string(static_cast<std::int64_t>(max_runs) * state.configurations_judged) +
          (state.configurations_judged < configurations
               ? ": a shard of " + std::to_string(state.configurations_judged) + " of the " +
                     std::to_string(configurations) + " configurations"
               : std::string()) +
          "), holding " + std::to_string(state.fits_wanted) + " of their " +
          std::to_string(state.fits_whole) + " fits (a decided cell's later fits left out)" +
          "; each cell at level " + number(state.cell_level, false) + " (" +
          (rule.correction == AdaptiveCorrection::kBonferroni
               ? "Bonferroni over the study's " + std::to_string(state.level_cells) +
                     " cells of level " + number(rule.level, false)
               : std::string("no correction over the cells")) +
          ")";
  return line;
}

std::vector<std::vector<std::string>> adaptive_cell_rows(const AdaptiveState& state,
                                                         const AdaptiveRule& rule, bool exact) {
  std::vector<std::vector<std::string>> rows;
  std::vector<std::string> header = {"compare"};
  if (!state.key_names.empty()) {
    header.insert(header.end(), state.key_names.front().begin(), state.key_names.front().end());
  }
  for (const char* name : {"metric", "state", "runs", "difference", "cs_low", "cs_high"}) {
    header.emplace_back(name);
  }
  rows.push_back(std::move(header));
  for (const AdaptiveCell& cell : state.cells) {
    const AdaptiveComparison& compare = rule.comparisons.at(cell.comparison);
    std::vector<std::string> row = {compare.axis + " " + compare.a + " - " + compare.b};
    row.insert(row.end(), cell.key.begin(), cell.key.end());
    row.push_back(cell.metric);
    row.emplace_back(cell_state_name(cell.state));
    row.push_back(std::to_string(cell.runs));
    row.push_back(number(cell.mean, exact));
    row.push_back(number(cell.lower, exact));
    row.push_back(number(cell.upper, exact));
    rows.push_back(std::move(row));
  }
  return rows;
}

}  // namespace ggk::engine
