#pragma once
// What `ggk run --resume` of an existing results file would compute, read only
// (`ggk validate` with an existing output): the complete runs it keeps, the runs
// it computes, the complete runs it grows by the fits of new values, and the time
// the fits would take at the file's own mean fit time (fit_seconds).
// A resume reads every kept run back first and computes a damaged one again; the
// preview does not read the runs' data, so it cannot foresee that.
//
// HDF5 calls: the caller's thread, one at a time.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "engine/hdf5/hdf5_file.hpp"
#include "engine/job/study.hpp"

namespace ggk::engine {

struct ResumePreview {
  bool grows = false;               // the job grows the file's (more runs or values)
  std::int64_t kept_runs = 0;       // complete runs that hold every fit of the job
  std::int64_t new_runs = 0;        // runs to compute whole
  std::int64_t new_run_fits = 0;    // their fits
  std::int64_t extended_runs = 0;   // complete runs that lack the fits of new values
  std::int64_t extension_fits = 0;  // those fits
  std::int64_t timed_fits = 0;      // fits of the file with a finite fit_seconds
  double mean_fit_seconds = 0.0;    // their mean (0 when there are none)
};

// Throws UsageError where `ggk run --resume` would refuse the file (another job,
// changed inputs, a group of a configuration the study lacks: resume_compatibility.hpp).
ResumePreview preview_resume(const Hdf5File& file, const Study& study,
                             const std::filesystem::path& output);

// The preview in words, one line each: what the resume keeps and computes, and
// the time estimate for `threads` (0: all cores), e.g.
//   "ggk run --resume would keep 2 complete runs and compute 2 runs (80 fits)"
//   "at the file's mean fit time (0.021 s over 80 fits): about 1.7 s of fitting on one
//    thread, 0.84 s at -j 2; the runs' samples and graphs come on top"
std::vector<std::string> preview_words(const ResumePreview& preview, const Study& study,
                                       std::int32_t threads);

}  // namespace ggk::engine
