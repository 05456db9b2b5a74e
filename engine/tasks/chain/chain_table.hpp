#pragma once
// The [chain] table of a job file (task = "chain"); keys, types and defaults in
// jobs/README.md.

#include "engine/job/toml_table_reader.hpp"
#include "sims/chain/chain.hpp"

namespace ggk::engine {

// Reads the [chain] table of `job` (the job file's root table; an absent [chain]
// means all defaults: the paper's 20-state chain). Throws JobError.
sims::chain::ChainConfig parse_chain_table(const TomlTableReader& job);

}  // namespace ggk::engine
