#pragma once
// Whether an existing results file may be resumed by a study, read only: the rules
// `ggk run --resume` applies before it writes anything (open_results.hpp), which
// `ggk validate` applies too to say what a resume would do (resume_preview.hpp).
//  - the same job: the root's layout, rules and task; the job compared by meaning
//    (job_resolved; as TOML text where an older ggk wrote none), the input files by
//    content; or a job the file grows into: more runs, more values of an axis
//    (never fewer, and a fit-level axis's values in the file's order);
//  - every configuration group of the file is one of the study's, found by its
//    values (attribute study_values), whatever its name.
// Each refusal is a UsageError naming the file and what differs.
//
// HDF5 calls: the caller's thread, one at a time.
#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "engine/hdf5/hdf5_file.hpp"
#include "engine/job/study.hpp"

namespace ggk::engine {

// The file holds `study`'s job (false) or a smaller one that `study` grows
// (true); otherwise a UsageError says what differs.
bool check_same_job(const Hdf5File& file, const Study& study, const std::filesystem::path& output);

}  // namespace ggk::engine
