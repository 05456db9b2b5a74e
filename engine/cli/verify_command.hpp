#pragma once
// `ggk verify FILE`: every dataset and attribute read back (store/results_verify.hpp)
// in a child process; exit 0 whole, 1 damaged (a file whose reading crashes HDF5
// included). A file that a live ggk writes now (its lock names a running process)
// may be caught between its writes: it is verified into a scratch file, and what
// looks damaged (or not yet a results file) is then said to be in writing, exit 2
// (verify it again later), not DAMAGED.
#include "engine/cli/command_line.hpp"

namespace ggk::engine {

// The exit status; user errors are thrown (UsageError).
int verify_command(const CommandLine& line);

}  // namespace ggk::engine
