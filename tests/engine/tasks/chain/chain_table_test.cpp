// The [chain] table: defaults are the paper's 20-state chain, every key is read,
// and bad values are refused at their key (rewarded states outside the chain,
// a chain of one state, widths the chain's distances cannot use).

#include "engine/tasks/chain/chain_table.hpp"

#include <string>

#include <gtest/gtest.h>

#include "engine/job/job_file.hpp"
#include "engine/tasks/task_list.hpp"
#include "support/job_text.hpp"

namespace ggk::engine {
namespace {

using test_support::no_output_check;

std::string chain_job(const std::string& sigma, const std::string& table) {
  return "name = \"c\"\ntask = \"chain\"\nruns = 1\nseed = 0\n[sweep]\nkernels = [4]\n"
         "sigma = [" +
         sigma + "]\n[chain]\n" + table;
}

// The JobError message of the job, or "ok".
std::string outcome(const std::string& text) {
  try {
    parse_job(text, "c.toml", task_tables(), no_output_check());
  } catch (const JobError& error) {
    return error.what();
  }
  return "ok";
}

TEST(ChainTable, DefaultsAreThePapersTwentyStateChain) {
  const JobSpec job = parse_job(chain_job("4.0", ""), "c.toml", task_tables(), no_output_check());
  const auto& config = task_config_as<sims::chain::ChainConfig>(job);
  EXPECT_EQ(config.states, 20);
  EXPECT_EQ(config.success, 0.9);
  EXPECT_EQ(config.rewarded, (std::vector<std::int32_t>{0, 19}));
  EXPECT_EQ(config.series * config.steps_per_series, 5000);
}

TEST(ChainTable, ReadsEveryKey) {
  const JobSpec job = parse_job(chain_job("4.0",
                                          "states = 50\nsuccess_probability = 0.8\n"
                                          "rewarded_states = [10, 41]\nseries = 20\n"
                                          "steps_per_series = 500\n"),
                                "c.toml", task_tables(), no_output_check());
  const auto& config = task_config_as<sims::chain::ChainConfig>(job);
  EXPECT_EQ(config.states, 50);
  EXPECT_EQ(config.success, 0.8);
  EXPECT_EQ(config.rewarded, (std::vector<std::int32_t>{9, 40}));
  EXPECT_EQ(config.series, 20);
  EXPECT_EQ(config.steps_per_series, 500);
  // The default rewarded states follow `states`: both ends.
  const JobSpec ends =
      parse_job(chain_job("4.0", "states = 7\n"), "c.toml", task_tables(), no_output_check());
  EXPECT_EQ(task_config_as<sims::chain::ChainConfig>(ends).rewarded,
            (std::vector<std::int32_t>{0, 6}));
}

TEST(ChainTable, RefusesBadValuesAtTheirKey) {
  EXPECT_NE(outcome(chain_job("4.0", "states = 1\n")).find("c.toml:9:1: [chain] states:"),
            std::string::npos);
  EXPECT_NE(
      outcome(chain_job("4.0", "rewarded_states = [0, 20]\n")).find("[chain] rewarded_states:"),
      std::string::npos);
  EXPECT_NE(
      outcome(chain_job("4.0", "rewarded_states = [1, 21]\n")).find("[chain] rewarded_states:"),
      std::string::npos);
  EXPECT_NE(
      outcome(chain_job("4.0", "success_probability = 1.5\n")).find("[chain] success_probability:"),
      std::string::npos);
  EXPECT_NE(outcome(chain_job("4.0", "series = 100000\nsteps_per_series = 100000\n"))
                .find("10000000000 samples per run"),
            std::string::npos);
  EXPECT_NE(outcome(chain_job("4.0", "slip = 0.1\n")).find("[chain]"), std::string::npos);
  // Far below neighbouring states' distance, every kernel value is 0.
  EXPECT_NE(outcome(chain_job("0.01", "")).find("[sweep] sigma:"), std::string::npos);
  EXPECT_EQ(outcome(chain_job("4.0", "")), "ok");
}

}  // namespace
}  // namespace ggk::engine
