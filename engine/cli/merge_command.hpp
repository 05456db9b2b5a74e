#pragma once
// `ggk merge OUT SHARD...` (or -o OUT SHARD..., or --shards-of JOB [--set ...]
// [--sweep ...] [-o OUT]): joins the shards of one job into the file the whole
// job writes (store/results_merge.hpp, in a child: run/isolated_merge.hpp).
#include <string>
#include <vector>

#include "engine/cli/command_line.hpp"

namespace ggk::engine {

// `invocation`: the command line as typed (its program names ggk in messages).
// The exit status; user errors are thrown (UsageError, JobError).
int merge_command(CommandLine& line, const std::vector<std::string>& invocation);

}  // namespace ggk::engine
