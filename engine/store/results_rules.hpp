#pragma once
// The rules a results file's numbers were computed under, beside its layout
// (results_layout.hpp: where things are). A change of ggk that changes what the
// same job computes (which random streams a run draws, what a fit tests on)
// raises kResultsRules: runs of two rules in one file would equal neither a file
// from scratch under the old ggk nor one under the new. So `run --resume` and
// `merge` refuse a file (or shard) of other rules, naming both; info, diff and
// verify read any.
//
//   rules 1: before common random numbers (ggk before commit 10a1054,
//            2026-11-26): a fit's test episodes drew streams of their own per
//            fit, the geodesic stretch depended on the fit's centres
//   rules 2: common random numbers: every fit of run r tests on run r's one
//            evaluation stream; the stretch is the graph's (between its first
//            100 centres); a fit depends only on its run and point
//
// Files record it as the root attribute `rules` (int64) from the commit that
// introduced it. Files without it were written under rules 1, except those of
// the commits from 10a1054 up to that one, which computed under rules 2 without
// saying so: their root attribute `git` (the commit, `git describe`) tells, by
// the list kept in results_rules.cpp.

#include <cstdint>
#include <string>
#include <string_view>

namespace ggk::engine {

inline constexpr std::int64_t kResultsRules = 2;

// The rules of a file without the attribute `rules`, from its attribute `git`
// ("0643028", "0643028-dirty"): 2 for the commits that wrote rules 2 unmarked,
// else 1.
std::int64_t rules_of_unmarked_file(std::string_view git);

// What rules `rules` mean, in a few words ("rules 1 (before common random
// numbers: ggk before 10a1054 of 2026-11-26)").
std::string rules_words(std::int64_t rules);

// Why runs of this ggk cannot be added to a file of results rules `rules`, or an
// empty string when they can.
std::string rules_mismatch(std::int64_t rules);

}  // namespace ggk::engine
