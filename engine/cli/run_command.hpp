#pragma once
// `ggk run JOB`: computes a job's runs into one results file, in this process
// (run/job_runner.hpp, run/adaptive_runner.hpp) or over the ranks of an MPI job
// (run/mpi_runner.hpp), after the checks of its options (--resume / --overwrite,
// -o with --set / --sweep, --runs, --shard) and the oversubscription warning.
#include <string>
#include <vector>

#include "engine/cli/command_line.hpp"

namespace ggk::engine {

class MpiSession;  // run/mpi_runner.hpp, in a build with MPI

// `invocation`: the command line as typed (the resume command repeats it);
// `mpi`: the session under an MPI launcher, else nullptr; `quiet_rank`: an MPI
// rank other than 0, which prints no warning. The exit status; user errors are
// thrown (UsageError, JobError), a failed run is RunFailure.
int run_command(CommandLine& line, const std::vector<std::string>& invocation, bool quiet_rank,
                MpiSession* mpi);

}  // namespace ggk::engine
