// An adaptive study's state (engine/store/adaptive_state.hpp) from hand-made
// contents: the looks replayed, each cell's decision, and what is refused.
#include "engine/store/adaptive_state.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "engine/job/usage_error.hpp"

namespace ggk::engine {
namespace {

// A study of one or two configurations, fits ggk and ogk at kernels 8; run r
// of configuration c has success_rate a(c, r) for ggk and b(c, r) for ogk.
ResultsContents contents_of(std::int32_t configurations, std::int32_t runs,
                            const std::function<double(int, int)>& a,
                            const std::function<double(int, int)>& b) {
  ResultsContents contents;
  contents.axis_names = {"basis", "kernels", "slip"};
  contents.metric_names = {"success_rate", "fit_seconds"};
  contents.metric_specs = {fraction_metric("success_rate", ""), fit_seconds_spec()};
  contents.configurations = static_cast<std::size_t>(configurations);
  for (std::int32_t c = 0; c < configurations; ++c) {
    for (std::int32_t r = 0; r < runs; ++r) {
      for (int side = 0; side < 2; ++side) {
        FitRow row;
        row.run = r;
        row.configuration = c;
        row.point = (static_cast<std::int64_t>(c) << 32) + side;
        row.key = {side == 0 ? "ggk" : "ogk", "8", c == 0 ? "0" : "0.1"};
        row.values = {side == 0 ? a(c, r) : b(c, r), 0.01};
        contents.fits.push_back(row);
      }
    }
  }
  return contents;
}

AdaptiveRule rule_of(std::int32_t batch) {
  AdaptiveRule rule;
  rule.comparisons = {{"basis", "ggk", "ogk"}};
  rule.metrics = {"success_rate"};
  rule.batch = batch;
  return rule;
}

// The same contents with every metric declared a mean (no range known).
ResultsContents as_means(ResultsContents contents) {
  for (MetricSpec& spec : contents.metric_specs) spec.kind = MetricKind::kMean;
  return contents;
}

TEST(AdaptiveState, LookOneAsksForABatchOfEveryConfiguration) {
  const AdaptiveState empty = adaptive_state({}, rule_of(5), 2, 40);
  EXPECT_EQ(empty.runs_wanted, (std::vector<std::int32_t>{5, 5}));
  EXPECT_FALSE(empty.done);
  // Three runs of five: the look goes on, nothing is judged beyond them.
  const ResultsContents three = contents_of(
      2, 3, [](int, int) { return 1.0; }, [](int, int) { return 0.0; });
  const AdaptiveState partial = adaptive_state(three, rule_of(5), 2, 40);
  EXPECT_EQ(partial.runs_wanted, (std::vector<std::int32_t>{5, 5}));
  EXPECT_EQ(partial.looks, 1);
  EXPECT_FALSE(partial.done);
  ASSERT_EQ(partial.cells.size(), 2u);
  EXPECT_EQ(partial.cells[0].state, CellState::kOpen);
  EXPECT_EQ(partial.cells[0].runs, 3);
}

TEST(AdaptiveState, AClearEffectIsDecidedAndStopsItsConfigurationOnly) {
  // Configuration 0: ggk always succeeds, ogk never (decided early);
  // configuration 1: the same success for both (never decided: capped).
  const auto a = [](int c, int r) { return c == 0 ? 1.0 : (r % 2 == 0 ? 0.75 : 0.25); };
  const auto b = [](int c, int r) { return c == 0 ? 0.0 : (r % 2 == 0 ? 0.25 : 0.75); };
  const AdaptiveState state = adaptive_state(contents_of(2, 40, a, b), rule_of(5), 2, 40);
  ASSERT_TRUE(state.done);
  ASSERT_EQ(state.cells.size(), 2u);
  EXPECT_DOUBLE_EQ(state.cell_level, 1.0 - 0.05 / 2.0);  // Bonferroni over 2 cells
  EXPECT_EQ(state.cells[0].state, CellState::kPositive);
  EXPECT_EQ(state.cells[0].key, (std::vector<std::string>{"8", "0"}));
  EXPECT_LT(state.runs_wanted[0], 40);
  EXPECT_EQ(state.cells[0].runs, state.runs_wanted[0]);
  EXPECT_DOUBLE_EQ(state.cells[0].mean, 1.0);
  EXPECT_GT(state.cells[0].lower, 0.0);
  EXPECT_EQ(state.cells[1].state, CellState::kCapped);
  EXPECT_EQ(state.runs_wanted[1], 40);
  EXPECT_EQ(state.cells[1].runs, 40);
  // Decided one batch earlier than it was: runs_wanted[0] - 5 runs did not do.
  const std::int32_t decided_at = state.runs_wanted[0];
  const AdaptiveState earlier =
      adaptive_state(contents_of(2, decided_at - 5, a, b), rule_of(5), 2, 40);
  EXPECT_EQ(earlier.cells[0].state, CellState::kOpen);
  // Runs beyond a look's are not judged: the state is that of the file's prefix.
  EXPECT_EQ(earlier.runs_wanted[0], decided_at);
}

TEST(AdaptiveState, ANegativeEffectAndAWidthTarget) {
  const auto low = [](int, int r) { return r % 3 == 0 ? 0.2 : 0.1; };
  const auto high = [](int, int r) { return r % 3 == 0 ? 0.9 : 1.0; };
  const AdaptiveState negative = adaptive_state(contents_of(1, 60, low, high), rule_of(5), 1, 60);
  ASSERT_TRUE(negative.done);
  EXPECT_EQ(negative.cells[0].state, CellState::kNegative);
  EXPECT_LT(negative.cells[0].upper, 0.0);
  AdaptiveRule width = rule_of(5);
  width.target = AdaptiveTarget::kWidth;
  width.width = 1.0;
  const AdaptiveState narrow = adaptive_state(contents_of(1, 60, low, high), width, 1, 60);
  ASSERT_TRUE(narrow.done);
  EXPECT_EQ(narrow.cells[0].state, CellState::kNarrow);
  EXPECT_LT(narrow.cells[0].upper - narrow.cells[0].lower, 1.0);
}

TEST(AdaptiveState, AFailedFitStopsItsCell) {
  const auto a = [](int, int r) { return r == 2 ? std::nan("") : 0.5; };
  const AdaptiveState state =
      adaptive_state(contents_of(1, 5, a, [](int, int) { return 0.5; }), rule_of(5), 1, 40);
  EXPECT_TRUE(state.done);
  EXPECT_EQ(state.cells[0].state, CellState::kFailed);
}

TEST(AdaptiveState, RefusesWhatItCannotJudge) {
  const ResultsContents contents = contents_of(
      1, 5, [](int, int) { return 0.5; }, [](int, int) { return 0.5; });
  AdaptiveRule unknown = rule_of(5);
  unknown.metrics = {"succes_rate"};
  EXPECT_THROW(adaptive_state(contents, unknown, 1, 40), UsageError);
  EXPECT_THROW(adaptive_state(as_means(contents), rule_of(5), 1, 40), UsageError);  // no range
  AdaptiveRule narrow_range = rule_of(5);
  narrow_range.ranges = {{"success_rate", 0.0, 0.25}};  // 0.5 lies outside
  try {
    adaptive_state(as_means(contents), narrow_range, 1, 40);
    FAIL() << "a value outside the range was accepted";
  } catch (const UsageError& e) {
    EXPECT_NE(std::string(e.what()).find("run 0 lies outside its range"), std::string::npos)
        << e.what();
  }
}

TEST(AdaptiveState, ADecidedCellKeepsItsVerdictWhileItsConfigurationGoesOn) {
  // Two metrics of one configuration: success_rate decided at once, `even`
  // (alternating +1 / -1 differences) never: the configuration runs to the cap,
  // the decided cell keeps the runs and bounds of its look.
  ResultsContents contents = contents_of(
      1, 30, [](int, int) { return 1.0; }, [](int, int) { return 0.0; });
  contents.metric_names = {"success_rate", "even", "fit_seconds"};
  contents.metric_specs.insert(contents.metric_specs.begin() + 1, fraction_metric("even", ""));
  for (FitRow& row : contents.fits) {
    const bool ggk = row.key[0] == "ggk";
    const double even = (row.run % 2 == 0) == ggk ? 1.0 : 0.0;
    row.values = {row.values[0], even, 0.01};
  }
  AdaptiveRule rule = rule_of(5);
  rule.metrics = {"success_rate", "even"};
  const AdaptiveState state = adaptive_state(contents, rule, 1, 30);
  ASSERT_TRUE(state.done);
  ASSERT_EQ(state.cells.size(), 2u);
  EXPECT_EQ(state.runs_wanted[0], 30);
  EXPECT_EQ(state.cells[1].state, CellState::kCapped);
  EXPECT_EQ(state.cells[0].state, CellState::kPositive);
  EXPECT_LT(state.cells[0].runs, 30);  // its look's runs, not the configuration's
}

TEST(AdaptiveState, TheAsymptoticMethodNeedsNoRange) {
  // A mean (no range known) differing by 10 with spread: decided, no range asked.
  const auto a = [](int, int r) { return 100.0 + 10.0 + (r % 3 == 0 ? 8.0 : -4.0); };
  const auto b = [](int, int r) { return 100.0 + (r % 2 == 0 ? 5.0 : -5.0); };
  AdaptiveRule rule = rule_of(5);
  rule.method = AdaptiveMethod::kAsymptotic;
  const AdaptiveState state = adaptive_state(as_means(contents_of(1, 40, a, b)), rule, 1, 40);
  ASSERT_TRUE(state.done);
  EXPECT_EQ(state.cells[0].state, CellState::kPositive);
  EXPECT_LE(state.cells[0].runs, 10);
  // The bounded method refuses it: no range.
  EXPECT_THROW(adaptive_state(as_means(contents_of(1, 40, a, b)), rule_of(5), 1, 40), UsageError);
}

TEST(AdaptiveState, AShardGoesThroughItsConfigurationsLooksAsTheWholeStudyDoes) {
  // Configuration 0 decided early, 1 capped (as above); the shard of
  // configuration 1 alone holds its runs only.
  const auto a = [](int c, int r) { return c == 0 ? 1.0 : (r % 2 == 0 ? 0.75 : 0.25); };
  const auto b = [](int c, int r) { return c == 0 ? 0.0 : (r % 2 == 0 ? 0.25 : 0.75); };
  const AdaptiveState whole = adaptive_state(contents_of(2, 40, a, b), rule_of(5), 2, 40);
  for (const std::int32_t own : {0, 1}) {
    ResultsContents shard = contents_of(2, 40, a, b);
    std::erase_if(shard.fits, [&](const FitRow& fit) {
      return fit.configuration != own || fit.run >= whole.runs_wanted[own];
    });
    // Without its scope the file's other configuration holds up look 1.
    EXPECT_FALSE(adaptive_state(shard, rule_of(5), 2, 40).done);
    const AdaptiveState state = adaptive_state(shard, rule_of(5), 2, 40, {{own}, 2});
    ASSERT_TRUE(state.done) << own;
    EXPECT_EQ(state.runs_wanted[own], whole.runs_wanted[own]);
    EXPECT_EQ(state.runs_wanted[1 - own], 0);  // the other shard's
    EXPECT_EQ(state.configurations_judged, 1);
    EXPECT_EQ(state.level_cells, 2);
    EXPECT_DOUBLE_EQ(state.cell_level, whole.cell_level);  // the study's two cells
    ASSERT_EQ(state.cells.size(), 1u);
    const AdaptiveCell& cell = state.cells[0];
    const AdaptiveCell& same = whole.cells[static_cast<std::size_t>(own)];
    EXPECT_EQ(cell.state, same.state);
    EXPECT_EQ(cell.runs, same.runs);
    EXPECT_EQ(cell.lower, same.lower);
    EXPECT_EQ(cell.upper, same.upper);
  }
  // A scope naming a configuration the study lacks (a damaged shard header).
  EXPECT_THROW(adaptive_state(contents_of(2, 5, a, b), rule_of(5), 2, 40, {{2}, 2}), UsageError);
}

// One configuration's points: ggk and ogk at kernels 2 and 8 (indices 0..3 as
// `index` gives them) and pvf at 8 (index 4, in no cell). Kernels 2: ggk 1,
// ogk 0 (decided at once); kernels 8: alternating differences (never decided).
struct CellPoint {
  std::string basis, kernels;
  std::int32_t index;
};
std::vector<CellPoint> cell_points(bool grown) {
  if (!grown) return {{"ggk", "8", 0}, {"ogk", "8", 1}, {"pvf", "8", 2}};  // before kernels 2
  return {{"ggk", "2", 0}, {"ggk", "8", 1}, {"ogk", "2", 2}, {"ogk", "8", 3}, {"pvf", "8", 4}};
}
FitRow cell_fit(const CellPoint& point, std::int64_t run) {
  FitRow row;
  row.run = run;
  row.point = point.index;
  row.key = {point.basis, point.kernels};
  const bool ggk = point.basis == "ggk";
  const double value = point.kernels == "2"   ? (ggk ? 1.0 : 0.0)
                       : point.basis == "pvf" ? 0.5
                                              : ((run % 2 == 0) == ggk ? 1.0 : 0.0);
  row.values = {value, 0.01};
  return row;
}
ResultsContents cell_contents() {
  ResultsContents contents;
  contents.axis_names = {"basis", "kernels"};
  contents.metric_names = {"success_rate", "fit_seconds"};
  contents.metric_specs = {fraction_metric("success_rate", ""), fit_seconds_spec()};
  return contents;
}
// Runs the study as the runner does: each look's new runs stored with the
// points they need, until done.
AdaptiveState run_cells(ResultsContents& contents, const AdaptiveRule& rule, std::int32_t runs) {
  for (int look = 0; look < 100; ++look) {
    const AdaptiveState state = adaptive_state(contents, rule, 1, runs);
    if (state.needs.empty()) return state;
    for (const RunNeed& need : state.needs) {
      EXPECT_TRUE(need.new_run);
      for (const CellPoint& point : cell_points(true)) {
        if (need.points.empty() ||
            std::count(need.points.begin(), need.points.end(), point.index) > 0) {
          contents.fits.push_back(cell_fit(point, need.run));
        }
      }
    }
  }
  ADD_FAILURE() << "no end after 100 looks";
  return {};
}

TEST(AdaptiveState, ADecidedCellsFitsAreLeftOutOfTheRunsAfterIt) {
  ResultsContents contents = cell_contents();
  AdaptiveRule rule = rule_of(5);
  const AdaptiveState state = run_cells(contents, rule, 30);
  ASSERT_TRUE(state.done);
  ASSERT_EQ(state.cells.size(), 2u);
  EXPECT_EQ(state.cells[0].state, CellState::kPositive);  // kernels 2
  EXPECT_EQ(state.cells[1].state, CellState::kCapped);    // kernels 8
  const std::int64_t decided_at = state.cells[0].runs;
  EXPECT_LT(decided_at, 30);
  // Every point up to the look that decided kernels 2, then kernels 8's and pvf's.
  ASSERT_EQ(state.run_points[0].size(), 2u);
  EXPECT_EQ(state.run_points[0][0].first_run, 0);
  EXPECT_EQ(state.run_points[0][0].points, (std::vector<std::int32_t>{0, 1, 2, 3, 4}));
  EXPECT_EQ(state.run_points[0][1].first_run, decided_at);
  EXPECT_EQ(state.run_points[0][1].points, (std::vector<std::int32_t>{1, 3, 4}));
  for (const FitRow& fit : contents.fits) {
    EXPECT_TRUE(fit.run < decided_at || fit.key[1] == "8") << fit.run << " " << fit.key[0];
  }
  EXPECT_EQ(state.fits_wanted, static_cast<std::int64_t>(contents.fits.size()));
  EXPECT_EQ(state.fits_whole, 30 * 5);
  EXPECT_EQ(state.fits_wanted, decided_at * 5 + (30 - decided_at) * 3);
  // The same file replayed: done, nothing needed (a resume computes nothing).
  EXPECT_TRUE(adaptive_state(contents, rule, 1, 30).needs.empty());
  // A run after the decision missing kernels 8's ogk fit: lacking it alone.
  ResultsContents lacking = contents;
  std::erase_if(lacking.fits, [&](const FitRow& fit) {
    return fit.run == decided_at && fit.key == std::vector<std::string>{"ogk", "8"};
  });
  const AdaptiveState extended = adaptive_state(lacking, rule, 1, 30);
  EXPECT_FALSE(extended.done);
  ASSERT_EQ(extended.needs.size(), 1u);
  EXPECT_FALSE(extended.needs[0].new_run);
  EXPECT_EQ(extended.needs[0].run, decided_at);
  EXPECT_EQ(extended.needs[0].points, (std::vector<std::int32_t>{3}));
}

TEST(AdaptiveState, AStudyGrownByAFitValueExtendsOrRenumbersItsRuns) {
  // The study of kernels 8 alone (indices 0..2) to its end, then grown by
  // kernels 2: the study's points are the planned ones.
  ResultsContents planned;
  planned.axis_names = {"basis", "kernels"};
  for (const CellPoint& point : cell_points(true)) planned.fits.push_back(cell_fit(point, 0));
  ResultsContents before = cell_contents();
  for (std::int64_t r = 0; r < 30; ++r) {
    for (const CellPoint& point : cell_points(false)) before.fits.push_back(cell_fit(point, r));
  }
  const AdaptiveRule rule = rule_of(5);
  ResultsContents whole = cell_contents();
  const AdaptiveState reference = run_cells(whole, rule, 30);
  const std::int64_t decided_at = reference.cells[0].runs;
  // Look 1 lacks kernels 2's points in runs 0..4: extensions by indices 0 and 2.
  const AdaptiveState grown = adaptive_state(before, rule, 1, 30, {}, &planned);
  EXPECT_FALSE(grown.done);
  ASSERT_EQ(grown.needs.size(), 5u);
  for (const RunNeed& need : grown.needs) {
    EXPECT_FALSE(need.new_run);
    EXPECT_EQ(need.points, (std::vector<std::int32_t>{0, 2}));
  }
  // Extended look by look: the runs after kernels 2 decided only renumbered.
  ResultsContents growing = before;
  std::int32_t renumbered = 0;
  for (int look = 0; look < 100; ++look) {
    const AdaptiveState state = adaptive_state(growing, rule, 1, 30, {}, &planned);
    if (state.needs.empty()) break;
    for (const RunNeed& need : state.needs) {
      ASSERT_FALSE(need.new_run);
      if (need.points.empty()) ++renumbered;
      std::erase_if(growing.fits, [&](const FitRow& fit) { return fit.run == need.run; });
      for (const CellPoint& point : cell_points(true)) {
        if (point.kernels == "8" ||
            std::count(need.points.begin(), need.points.end(), point.index) > 0) {
          growing.fits.push_back(cell_fit(point, need.run));
        }
      }
    }
  }
  EXPECT_EQ(renumbered, 30 - decided_at);
  const AdaptiveState after = adaptive_state(growing, rule, 1, 30, {}, &planned);
  EXPECT_TRUE(after.done);
  EXPECT_EQ(after.run_points, reference.run_points);
  ASSERT_EQ(after.cells.size(), reference.cells.size());
  for (std::size_t i = 0; i < after.cells.size(); ++i) {
    EXPECT_EQ(after.cells[i].state, reference.cells[i].state);
    EXPECT_EQ(after.cells[i].runs, reference.cells[i].runs);
  }
}

// Planned fits of three configurations (slip 0, 0.1, 0.2), ggk and ogk each.
ResultsContents planned_slips() {
  ResultsContents planned;
  planned.axis_names = {"basis", "slip"};
  planned.configurations = 3;
  const std::vector<std::string> slips = {"0", "0.1", "0.2"};
  for (std::int32_t c = 0; c < 3; ++c) {
    for (int side = 0; side < 2; ++side) {
      FitRow row;
      row.configuration = c;
      row.point = (static_cast<std::int64_t>(c) << 32) + side;
      row.key = {side == 0 ? "ggk" : "ogk", slips[static_cast<std::size_t>(c)]};
      planned.fits.push_back(row);
    }
  }
  return planned;
}

TEST(AdaptivePlan, LinksTheConfigurationsACellCompares) {
  // Over a fit axis each configuration is its own group: 3 cells per metric.
  AdaptiveRule rule = rule_of(5);
  rule.metrics = {"success_rate", "mean_steps"};
  const AdaptivePlan by_basis = adaptive_plan(planned_slips(), rule, 3);
  EXPECT_EQ(by_basis.cells, 6);
  EXPECT_EQ(by_basis.groups, 3);
  EXPECT_EQ(by_basis.group_of, (std::vector<std::int32_t>{0, 1, 2}));
  // Over the study axis slip = 0, 0.1: configurations 0 and 1 linked, one cell
  // per basis; slip 0.2 is in no cell, a group alone.
  rule.comparisons = {{"slip", "0", "0.1"}};
  const AdaptivePlan by_slip = adaptive_plan(planned_slips(), rule, 3);
  EXPECT_EQ(by_slip.cells, 4);
  EXPECT_EQ(by_slip.groups, 2);
  EXPECT_EQ(by_slip.group_of, (std::vector<std::int32_t>{0, 0, 1}));
  // Both: 0.1 against 0.2 as well links all three.
  rule.comparisons.push_back({"slip", "0.1", "0.2"});
  const AdaptivePlan chained = adaptive_plan(planned_slips(), rule, 3);
  EXPECT_EQ(chained.groups, 1);
  EXPECT_EQ(chained.group_of, (std::vector<std::int32_t>{0, 0, 0}));
}

}  // namespace
}  // namespace ggk::engine
