#pragma once
// `ggk info FILE`: what a results file holds (store/results_info.hpp), read in a
// child process (run/isolated_reading.hpp): --csv, --columns, --paired, --adaptive.
#include "engine/cli/command_line.hpp"

namespace ggk::engine {

// The exit status; user errors are thrown (UsageError).
int info_command(const CommandLine& line);

}  // namespace ggk::engine
