#pragma once
// `ggk validate JOB`: a dry run of `ggk run` with the same arguments. It refuses
// what run would refuse (the job, the overrides, the output, the memory at -j),
// prints the runs, sweep points and memory per run, and with an existing output
// what --resume would compute (run/resume_preview.hpp); --print prints the
// resolved job as TOML (job/study.hpp: resolved_job_toml).
#include "engine/cli/command_line.hpp"

namespace ggk::engine {

// The exit status; user errors are thrown (UsageError, JobError).
int validate_command(const CommandLine& line);

}  // namespace ggk::engine
