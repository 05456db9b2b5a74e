#pragma once
// Runs an adaptive study (job/adaptive_rule.hpp): look after look, the runs the
// rule asks for (store/adaptive_state.hpp decides from the file's complete runs),
// computed as oneTBB tasks and committed by the one JobWriter, until no cell asks
// for more. Each look is a growth by runs of the same file, so a study stopped at
// any point and resumed (--resume) ends equal to one never stopped.
//
// Not yet: MPI and shards (--runs, --shard), which the runner refuses (exit 2).

#include <string>
#include <vector>

#include "engine/job/study.hpp"
#include "engine/run/job_runner.hpp"
#include "engine/store/adaptive_state.hpp"

namespace ggk::engine {

// The rule's metrics have ranges: declared, or rates and fractions of the task.
// Throws UsageError naming the metric ([adaptive.range]).
void check_adaptive_metrics(const Study& study);

// The rule in words, for `ggk validate`: "adaptive: runs 5 at a time up to 60 per
// run configuration while a cell of basis=ggk,ogk on success_rate is undecided
// (its sign; bernstein confidence sequence, level 0.95 over all cells)".
std::string adaptive_rule_words(const AdaptiveRule& rule, std::int32_t runs);

// run_study for a study whose job has an [adaptive] table.
RunSummary run_adaptive_study(const Study& study, const RunOptions& options);

// The closing lines of an adaptive study: looks, cells decided, open, capped,
// and the runs spent against the fixed design's.
std::vector<std::string> adaptive_summary_lines(const AdaptiveState& state, const Study& study);

}  // namespace ggk::engine
