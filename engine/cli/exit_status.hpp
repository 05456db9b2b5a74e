#pragma once
// How a command's failure becomes ggk's exit status and its one line on stderr:
// the user's mistakes (JobError, UsageError, and an allocation that failed: the
// machine's memory or the user's limit) are "ggk: error: ..." and status 2; a
// failed run (RunFailure) is "ggk: error: ..." and status 1; anything else is
// "ggk: internal error: ..." and status 1.
#include <functional>

namespace ggk::engine {

inline constexpr int kUserErrorStatus = 2;

// Runs `command` and returns its exit status, or the status of what it threw.
// `quiet_rank`: an MPI rank other than 0 prints no user error (rank 0 does).
int exit_status_of(const std::function<int()>& command, bool quiet_rank);

}  // namespace ggk::engine
