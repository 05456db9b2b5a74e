#pragma once
// `ggk diff A B`: whether two results files hold the same results
// (store/results_diff.hpp), read in a child process; exit 0 same, 1 different.
#include "engine/cli/command_line.hpp"

namespace ggk::engine {

// The exit status; user errors are thrown (UsageError).
int diff_command(const CommandLine& line);

}  // namespace ggk::engine
