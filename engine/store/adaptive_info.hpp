#pragma once
// How `ggk info` shows an adaptive study (adaptive_state.hpp): one status line
// (looks, cells decided / open / capped, runs per configuration), and a table of
// the cells: the comparison, the other axes' values, the metric, the state, the
// paired runs judged, the mean difference and its confidence sequence's bounds.
//
// Thread-safety: pure functions.
#include <cstdint>
#include <string>
#include <vector>

#include "engine/job/adaptive_rule.hpp"
#include "engine/store/adaptive_state.hpp"

namespace ggk::engine {

// "adaptive: look 3, done: 5 of 6 cells decided (+ 4, - 1), 1 capped; runs per
// configuration 15, 60 (at most 60); each cell at level 0.99167 (bonferroni over
// 6 cells of level 0.95)".
std::string adaptive_status_line(const AdaptiveState& state, const AdaptiveRule& rule,
                                 std::int32_t max_runs);

// The cells as rows, the first the column names: compare, the other axes (of
// the first comparison; a later one's differ where its axis does), metric,
// state, runs, difference, cs_low, cs_high. `exact`: numbers in their shortest
// exact form (CSV), else to 4 significant digits.
std::vector<std::vector<std::string>> adaptive_cell_rows(const AdaptiveState& state,
                                                         const AdaptiveRule& rule, bool exact);

}  // namespace ggk::engine
