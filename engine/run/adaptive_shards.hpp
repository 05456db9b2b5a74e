#pragma once
// Shards of an adaptive study (`ggk run JOB --shard I/N` or `--shard slurm` on a
// job with an [adaptive] table). A shard of runs cannot work: the rule decides on
// every run of a configuration. So an adaptive study is split by run
// configurations instead, in groups the rule's cells never link: two
// configurations are in one group when a cell compares them (a comparison over
// a study axis, `compare = "maze.slip=0.0,0.1"`); under a comparison over a fit
// axis (`basis=ggk,ogk`) both sides are fits of one configuration, each its own
// group. Shard I holds groups floor(I G / N) .. floor((I+1) G / N) - 1 of the G
// groups (numbered by their first configuration). A group goes through the same
// looks in its shard as in the whole study (store/adaptive_state.hpp): each cell
// is judged at the whole study's level, whose cell count the shard file
// records (adaptive_cells), so the shards merged (`ggk merge --shards-of JOB`)
// are `ggk diff`-equal to the study run whole.

#include <cstdint>

#include "engine/job/study.hpp"
#include "engine/run/job_runner.hpp"
#include "engine/run/shards.hpp"
#include "engine/store/adaptive_state.hpp"
#include "engine/store/results_contents.hpp"

namespace ggk::engine {

// Every fit the study plans, as a results file will list it (one row per
// configuration and sweep point, run 0, its axes; no values).
ResultsContents planned_contents(const Study& study);

// The study's cells and the groups of configurations they link. Throws UsageError
// for a rule comparing an axis the study lacks (as the first look would).
AdaptivePlan adaptive_plan_of(const Study& study);

// `ggk run JOB --shard` on an adaptive study: options.configuration_shard = the
// shard's groups' configurations with the study's cells, options.output = the
// shard's file (as select_shard names it). Refuses N above the groups' count.
void select_adaptive_shard(const Shard& shard, const Study& study, RunOptions& options);

}  // namespace ggk::engine
