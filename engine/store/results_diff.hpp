#pragma once
// `ggk diff A.h5 B.h5`: do two results files hold the same results? ("did my
// cluster run reproduce my laptop run?")
//
// Compared, bit for bit (NaNs included): every group, dataset and attribute of
// both files, by path. Not compared:
//  - wall-clock values: every `fit_seconds` attribute and table column, and the
//    root's `created`;
//  - provenance, which says how and where a file was made, not what it holds:
//    the root's `job_file` (the path as typed), `git`, `ggk_version`, `blas` and
//    `runs_selected` (a shard's range); differences there are printed as notes;
//  - the /.staging group (the writer's scratch space).

#include <filesystem>
#include <ostream>

namespace ggk::engine {

// Prints the verdict (and the first differences, by path) to `out`; returns true
// when the results are the same. Throws UsageError when a file cannot be read as
// a ggk results file.
bool diff_results(const std::filesystem::path& a, const std::filesystem::path& b,
                  std::ostream& out);

}  // namespace ggk::engine
