#pragma once
// `ggk diff A.h5 B.h5`: do two results files hold the same results? ("did my
// cluster run reproduce my laptop run?")
//
// Compared, bit for bit by default (NaNs included): every group, dataset and
// attribute of both files, by path. With a tolerance (--rtol R, --atol A), float
// elements are equal when |a - b| <= A + R |b| (value_difference.hpp); integers
// and strings stay exact. Every differing dataset or attribute is printed with how
// many elements differ and the largest absolute and relative difference and
// where; a verdict within tolerance says how many differed bit for bit and by how
// much at most. Objects whose printed path ("/maze/run_000/fits/.../weights", or
// "/ @job" for an attribute) matches a --exclude glob (fnmatch: `*` also matches
// '/') are not compared, e.g. --exclude '*/history/*' for the solver's
// per-iteration diagnostics, which differ by design between linear_algebra
// kinds. Not compared either:
//  - wall-clock values: every `fit_seconds` attribute and table column, and the
//    root's `created`;
//  - provenance, which says how and where a file was made, not what it holds:
//    the root's `job_file` (the path as typed), `git`, `ggk_version`, `blas` and
//    `runs_selected` (a shard's range); differences there are printed as notes;
//  - the /.staging group (the writer's scratch space).
// Where both files record their jobs' meaning (job_resolved) and the jobs differ,
// every key that differs is named in a note (the job is provenance: the results
// say whether they are the same), and the files are compared by value: a study's
// configuration groups paired by their values (study_values), fits by their
// group names (which are their points), the fit tables (fit_metrics, summary)
// row by row matched by the point's columns; the numbering (sweep_point,
// configuration) is then not compared. With `common`, what one file holds and
// the other does not is a note: `ggk diff --common` of a study with slip 0.0, 0.2
// against one with 0.0, 0.1, 0.2 compares the points both hold.
// `ggk diff` exits 0 when the results are the same (within the tolerance), 1 when
// they differ, 2 on a usage error (a file that is no results file, two files of
// different tasks, a negative tolerance).

#include <filesystem>
#include <ostream>
#include <string>
#include <vector>

#include "engine/store/value_difference.hpp"

namespace ggk::engine {

// Prints the verdict (and every difference, by path) to `out`; returns true when
// the results are the same within the options' tolerance. Throws UsageError when a file
// cannot be read as a ggk results file, when the two files hold different tasks,
// or when a tolerance is negative or not a number.
struct DiffOptions {
  Tolerance tolerance;
  std::vector<std::string> exclude;  // fnmatch globs on printed paths
  // What only one file holds (a configuration, run, fit or row of a study with
  // other values) is a note, not a difference: the points both hold are compared.
  bool common = false;
};

bool diff_results(const std::filesystem::path& a, const std::filesystem::path& b, std::ostream& out,
                  const DiffOptions& options = {});

}  // namespace ggk::engine
