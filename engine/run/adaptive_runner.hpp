#pragma once
// Runs an adaptive study (job/adaptive_rule.hpp): look after look, the runs the
// rule asks for (store/adaptive_state.hpp decides from the file's complete runs),
// computed as oneTBB tasks (or, under mpirun, over the ranks: mpi_runner.hpp)
// and committed by the one JobWriter, until no cell asks for more. Each look is a
// growth by runs of the same file and its decisions a function of the file's
// runs alone, so a study stopped at any point and resumed (--resume), or run
// over any number of ranks, ends equal to one run whole in one process.
//
// Shards split it by run configurations (--shard I/N: adaptive_shards.hpp), each
// shard's looks over its own; not by runs (--runs: refused, exit 2), as the rule
// decides on every run of a configuration.

#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "engine/job/study.hpp"
#include "engine/run/job_runner.hpp"
#include "engine/run/job_writer.hpp"
#include "engine/store/adaptive_state.hpp"

namespace ggk::engine {

// The rule's metrics have ranges: declared, or rates and fractions of the task.
// Throws UsageError naming the metric ([adaptive.range]).
void check_adaptive_metrics(const Study& study);

// The rule in words, for `ggk validate`: "adaptive: runs 5 at a time up to 60 per
// run configuration while a cell of basis=ggk,ogk on success_rate is undecided
// (its sign; bernstein confidence sequence, level 0.95 over all cells)".
std::string adaptive_rule_words(const AdaptiveRule& rule, std::int32_t runs);

// The looks of an adaptive study. Used by one thread (the one that commits or
// coordinates).
class AdaptiveLooks {
 public:
  // `options`: a shard's configurations (configuration_shard), or all.
  AdaptiveLooks(const Study& study, const RunOptions& options);

  // The units of the next look, decided from the file's complete runs (read
  // through `writer`, after every committed run is written: call writer.wait()
  // first): the runs the rule now asks for that the file lacks, each with the
  // points its open cells need (AdaptiveState::needs), and stored runs lacking
  // points they need (a study grown by fit-level values: extensions). Counted
  // in the writer's progress (its stage names the look and the open cells).
  // Empty when the study is done.
  std::vector<WorkUnit> next_look(JobWriter& writer);

  const AdaptiveState& state() const { return state_; }
  // The units handed out by next_look so far.
  std::int32_t computed() const { return computed_; }
  // The runs the rule uses: every configuration's runs_wanted, summed.
  std::int64_t runs_used() const;

 private:
  const Study& study_;
  AdaptiveScope scope_;
  ResultsContents planned_;  // the study's sweep points (adaptive_shards.hpp)
  AdaptiveState state_;
  std::int32_t computed_ = 0;
};

// An adaptive study's runs are its rule's: a UsageError for --runs.
void refuse_adaptive_shards(const Study& study, const RunOptions& options);

// run_study for a study whose job has an [adaptive] table.
RunSummary run_adaptive_study(const Study& study, const RunOptions& options);

// The closing lines of an adaptive study (or shard: `options`): looks, cells
// decided, open, capped, and the runs spent against the fixed design's.
std::vector<std::string> adaptive_summary_lines(const AdaptiveState& state, const Study& study,
                                                const RunOptions& options);

}  // namespace ggk::engine
