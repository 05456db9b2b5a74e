#pragma once
// The refusal of `ggk run` (without --resume or --overwrite) for an output that
// exists, saying whose it is: one another ggk writes (its lock) is not read; else
// read in a child (isolated_reading.hpp: the file is not ggk's to trust), a file
// `--resume` would refuse (another job's) is named so,
// and where it is the job file's own [output] file, the likely cause: a job file
// copied from another keeps the original's `name` and `[output] file`.
#include <filesystem>
#include <string>

#include "engine/job/study.hpp"

namespace ggk::engine {

// The message: "output F exists: pass --resume to continue it, or --overwrite to
// replace it (deleting its complete runs)", or for another job's file "output F
// exists and holds the results of a different job (...)" with what to do.
// `own_output`: F is the job's [output] file (no -o).
std::string existing_output_refusal(const Study& study, const std::filesystem::path& output,
                                    bool own_output);

}  // namespace ggk::engine
