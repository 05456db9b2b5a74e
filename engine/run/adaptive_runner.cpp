#include "engine/run/adaptive_runner.hpp"

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "engine/job/usage_error.hpp"
#include "engine/run/job_writer.hpp"
#include "engine/run/open_results.hpp"
#include "engine/store/results_contents.hpp"
#include "engine/tasks/task_list.hpp"

namespace ggk::engine {
namespace {

// The study's state from the file's complete runs, leaving out those still to
// compute (`outstanding`: missing, or lacking fits of a grown study).
AdaptiveState state_of_file(
    const Hdf5File& file, const Study& study, const AdaptiveScope& scope,
    const std::map<std::pair<std::int32_t, std::int32_t>, WorkUnit>& outstanding) {
  ResultsContents contents = read_contents(file);
  std::erase_if(contents.fits, [&](const FitRow& fit) {
    return outstanding.count({fit.configuration, static_cast<std::int32_t>(fit.run)}) > 0;
  });
  return adaptive_state(contents, *study.job().adaptive,
                        static_cast<std::int32_t>(study.configurations.size()), study.job().runs,
                        scope);
}

std::string stage_text(const AdaptiveState& state) {
  if (state.cells.empty()) return "look " + std::to_string(state.looks);
  return "look " + std::to_string(state.looks) + ", " + std::to_string(state.open_cells()) +
         " of " + std::to_string(state.cells.size()) + " cells open";
}

}  // namespace

void check_adaptive_metrics(const Study& study) {
  const std::optional<AdaptiveRule>& rule = study.job().adaptive;
  if (!rule) return;
  const TaskDefinition* task = find_task(study.job().task);
  const std::vector<MetricSpec> specs = task != nullptr && task->metric_specs != nullptr
                                            ? task->metric_specs(study.job())
                                            : std::vector<MetricSpec>{};
  for (const std::string& metric : rule->metrics) {
    if (metric_range(*rule, metric, declared_kind(specs, metric))) continue;
    // The rule's ranges are its own (a decision never follows a range the file's
    // configurations declare): the task's declaration is only suggested.
    const MetricSpec* spec = find_metric_spec(specs, metric);
    const bool bounded = spec != nullptr && std::isfinite(spec->low) && std::isfinite(spec->high);
    throw UsageError(
        "[adaptive] metrics: '" + metric + "' is no rate or fraction of task '" + study.job().task +
        "', so its range is unknown: give it as [adaptive.range] " + metric + " = [LOW, HIGH] (" +
        (bounded ? "the task declares [" + as_text(TableValue(spec->low)) + ", " +
                       as_text(TableValue(spec->high)) + "] for this job"
                 : std::string("the bounds the task's rewards and episode length put on it")) +
        ")");
  }
}

std::string adaptive_rule_words(const AdaptiveRule& rule, std::int32_t runs) {
  std::string compared, metrics;
  for (const AdaptiveComparison& c : rule.comparisons) {
    compared += (compared.empty() ? "" : ", ") + c.text();
  }
  for (const std::string& m : rule.metrics) metrics += (metrics.empty() ? "" : ", ") + m;
  char level[32];
  std::snprintf(level, sizeof level, "%g", rule.level);
  return "adaptive: runs " + std::to_string(rule.batch) + " at a time up to " +
         std::to_string(runs) + " per run configuration while a cell of " + compared + " on " +
         metrics + " is undecided (" +
         (rule.target == AdaptiveTarget::kSign ? std::string("its sign")
                                               : "narrower than " + std::to_string(rule.width)) +
         "; " + (rule.method == AdaptiveMethod::kBernstein ? "bernstein" : "asymptotic") +
         " confidence sequences, " +
         (rule.correction == AdaptiveCorrection::kBonferroni
              ? "Bonferroni: level " + std::string(level) + " over all cells"
              : "level " + std::string(level) + " per cell") +
         ")";
}

std::vector<std::string> adaptive_summary_lines(const AdaptiveState& state, const Study& study,
                                                const RunOptions& options) {
  std::int64_t decided = 0, capped = 0, failed = 0;
  for (const AdaptiveCell& cell : state.cells) {
    if (cell.state == CellState::kCapped)
      ++capped;
    else if (cell.state == CellState::kFailed)
      ++failed;
    else if (cell.state != CellState::kOpen)
      ++decided;
  }
  std::int64_t runs = 0;
  for (const std::int32_t wanted : state.runs_wanted) runs += wanted;
  const std::size_t configurations = options.configuration_shard
                                         ? options.configuration_shard->scope.configurations.size()
                                         : study.configurations.size();
  const std::int64_t fixed =
      static_cast<std::int64_t>(study.job().runs) * static_cast<std::int64_t>(configurations);
  std::vector<std::string> lines;
  lines.push_back(
      "adaptive: " + std::string(state.done ? "done" : "not done") + " after " +
      std::to_string(state.looks) + " looks: " + std::to_string(decided) + " of " +
      std::to_string(state.cells.size()) +
      (options.configuration_shard ? " cells of this shard decided, " : " cells decided, ") +
      std::to_string(state.open_cells()) + " open, " + std::to_string(capped) + " capped at " +
      std::to_string(study.job().runs) + " runs" +
      (failed > 0 ? ", " + std::to_string(failed) + " with failed fits" : "") + "; " +
      std::to_string(runs) + " runs, against " + std::to_string(fixed) +
      (options.configuration_shard ? " for its configurations at their most"
                                   : " for every configuration at its most") +
      " (ggk info shows the cells)");
  return lines;
}

AdaptiveLooks::AdaptiveLooks(const Study& study, const RunOptions& options,
                             const std::vector<WorkUnit>& pending)
    : study_(study),
      scope_(options.configuration_shard ? options.configuration_shard->scope : AdaptiveScope{}) {
  for (const WorkUnit& unit : pending) outstanding_[{unit.configuration, unit.run}] = unit;
}

std::vector<WorkUnit> AdaptiveLooks::next_look(JobWriter& writer) {
  state_ = writer.read(
      [&](Hdf5File& file) { return state_of_file(file, study_, scope_, outstanding_); });
  std::vector<WorkUnit> look;
  for (std::size_t c = 0; c < study_.configurations.size(); ++c) {
    for (std::int32_t run = 0; run < state_.runs_wanted[c]; ++run) {
      const auto at = outstanding_.find({static_cast<std::int32_t>(c), run});
      if (at != outstanding_.end()) look.push_back(at->second);
    }
  }
  writer.set_stage(stage_text(state_));
  if (look.empty()) {
    if (state_.done) return look;
    throw std::logic_error("adaptive study: look " + std::to_string(state_.looks) +
                           " lacks runs but none is outstanding");
  }
  writer.add_runs_to_write(static_cast<std::int32_t>(look.size()));
  writer.expect_units(look);
  for (const WorkUnit& unit : look) outstanding_.erase({unit.configuration, unit.run});
  computed_ += static_cast<std::int32_t>(look.size());
  return look;
}

std::int64_t AdaptiveLooks::runs_used() const {
  std::int64_t used = 0;
  for (const std::int32_t wanted : state_.runs_wanted) used += wanted;
  return used;
}

void refuse_adaptive_shards(const Study& study, const RunOptions& options) {
  if (study.job().adaptive && options.runs) {
    throw UsageError(
        "an adaptive study chooses its runs by its rule ([adaptive]) from all of them: run it "
        "without --runs (a range of runs cannot see the other runs its rule decides on), "
        "whole or in shards by run configurations with --shard I/N");
  }
}

RunSummary run_adaptive_study(const Study& study, const RunOptions& options) {
  refuse_adaptive_shards(study, options);
  const auto started = std::chrono::steady_clock::now();
  const ComputeThreads threads(options.threads);
  check_adaptive_metrics(study);
  check_study_memory(study, options);  // before the output is created or touched
  OpenedResults opened = open_results(study, options);
  print_notes(opened.notes);
  if (!options.quiet) print_notes(opened.info);
  RunSummary summary;
  summary.output = opened.target.output();
  AdaptiveLooks looks(study, options, opened.pending);

  RunTally tally;
  JobWriter writer(study, options, std::move(opened), 0, StopSignals::Mode::kStopInHandler);
  try {
    for (;;) {
      const std::vector<WorkUnit> look = looks.next_look(writer);
      if (look.empty()) break;
      compute_units(study, look, writer, tally);
      writer.wait();
    }
    writer.finish();
  } catch (const UsageError&) {
    throw;
  } catch (const std::runtime_error& e) {
    throw stopped_job(writer, e);
  }
  summary.runs_computed = looks.computed();
  summary.runs_skipped = static_cast<std::int32_t>(looks.runs_used() - looks.computed());
  summary.fits = tally.fits.load();
  summary.failed_fits = tally.failed_fits.load();
  summary.warnings = tally.warnings.lines();
  summary.adaptive = adaptive_summary_lines(looks.state(), study, options);
  summary.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  return summary;
}

}  // namespace ggk::engine
