#include "engine/tasks/chain/chain_table.hpp"

#include <array>
#include <cstdint>
#include <string_view>
#include <vector>

#include "engine/job/kernel_width.hpp"
#include "engine/job/walk_sizes.hpp"

namespace ggk::engine {

namespace {

constexpr std::array<std::string_view, 5> kChainKeys = {
    "states", "success_probability", "rewarded_states", "series", "steps_per_series"};

}  // namespace

sims::chain::ChainConfig parse_chain_table(const TomlTableReader& job) {
  const TomlTableReader chain = job.subtable_or_empty("chain", kChainKeys);
  sims::chain::ChainConfig config;
  config.states = static_cast<std::int32_t>(chain.integer("states", {2, 1'000'000}, config.states));
  config.success = chain.number("success_probability", {0.0, true, 1.0, true}, config.success);
  // 1-based, as the paper numbers the states; default: both ends.
  const std::vector<std::int64_t> rewarded = chain.integer_set(
      "rewarded_states", {1, config.states}, std::vector<std::int64_t>{1, config.states});
  config.rewarded.assign(rewarded.begin(), rewarded.end());
  for (std::int32_t& state : config.rewarded) --state;
  const WalkSizes walks = read_walk_sizes(chain, {config.series, config.steps_per_series});
  config.series = walks.series;
  config.steps_per_series = walks.steps_per_series;
  // State vectors are positions 1 .. states: neighbours are 1 apart; a kernel's
  // distance is at most a path along the chain plus the distance to the nearest
  // graph node, each at most states - 1.
  const double length = config.states - 1.0;
  check_kernel_widths(
      job, {1.0, 2.0 * length, "between neighbouring states", "twice the chain's length"});
  return config;
}

}  // namespace ggk::engine
