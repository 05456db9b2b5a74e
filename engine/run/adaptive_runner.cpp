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
#include "engine/run/adaptive_shards.hpp"
#include "engine/run/job_writer.hpp"
#include "engine/run/open_results.hpp"
#include "engine/store/results_contents.hpp"
#include "engine/tasks/task_list.hpp"

namespace ggk::engine {
namespace {

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
      "; " + std::to_string(state.fits_wanted) + " fits, against " +
      std::to_string(state.fits_whole) + " had the runs fitted decided cells too" +
      " (ggk info shows the cells)");
  return lines;
}

AdaptiveLooks::AdaptiveLooks(const Study& study, const RunOptions& options)
    : study_(study),
      scope_(options.configuration_shard ? options.configuration_shard->scope : AdaptiveScope{}),
      planned_(planned_contents(study)) {}

std::vector<WorkUnit> AdaptiveLooks::next_look(JobWriter& writer) {
  state_ = writer.read([&](Hdf5File& file) {
    return adaptive_state(read_contents(file), *study_.job().adaptive,
                          static_cast<std::int32_t>(study_.configurations.size()),
                          study_.job().runs, scope_, &planned_);
  });
  std::vector<WorkUnit> look;
  for (const RunNeed& need : state_.needs) {
    look.push_back({need.configuration, need.run, need.points, !need.new_run});
  }
  writer.set_stage(stage_text(state_));
  if (look.empty()) {
    if (state_.done) return look;
    throw std::logic_error("adaptive study: look " + std::to_string(state_.looks) +
                           " lacks runs but needs none");
  }
  writer.add_runs_to_write(static_cast<std::int32_t>(look.size()));
  writer.expect_units(look);
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
  AdaptiveLooks looks(study, options);

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
