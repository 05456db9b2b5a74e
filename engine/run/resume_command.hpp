#pragma once
// What ggk tells the user when `ggk run` stops before the end (a signal, a
// failed run or write, a dead MPI rank): what the output holds and the command
// that goes on, ready to paste into a POSIX shell.
//
// The command is the invocation as typed (RunOptions::invocation: the program
// as invoked, every --set, --runs, -o, -j ... kept, so a shard resumes as the
// same shard and overrides as the same job) with --overwrite replaced by
// --resume and --resume added once. Library callers that give no invocation get
// `ggk run JOB [--set K=V]... [--runs A:B] -o OUTPUT --resume`. Under MPI the
// launcher's own arguments are not visible to ggk: the text says to run the
// command under mpirun as before (with any number of ranks) or alone.

#include <filesystem>
#include <string>

#include "engine/job/job_spec.hpp"

namespace ggk::engine {

struct RunOptions;

// The shell command that finishes the job into `output`.
std::string resume_command(const JobSpec& job, const RunOptions& options,
                           const std::filesystem::path& output);

// The two ends of a sentence such as "interrupted (SIGINT); <text>".
struct GoOnText {
  // Runs of this job are in the output: "every run written to OUT is complete;
  // finish the job with `COMMAND`".
  std::string published;
  // No run of this job reached the output: "OUT is as it was (...); start the
  // job again with `INVOCATION`" (as typed; with --overwrite, the text says
  // that it deletes the runs OUT holds).
  std::string unpublished;
};

GoOnText go_on_text(const JobSpec& job, const RunOptions& options,
                    const std::filesystem::path& output, bool under_mpi);

}  // namespace ggk::engine
