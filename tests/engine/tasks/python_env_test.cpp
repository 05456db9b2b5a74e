// The python_env task (engine/tasks/python_env/) against the C++ simulators:
// the project's Python twins (tests/python/envs/ggk_test_envs) compute the same
// dynamics operation for operation, so every sample they make through ggk
// replays bit for bit in sims/mountain_car and sims/pendulum; the task's series
// end at `terminated` (absorbing) and at `truncated` (not absorbing). The chain
// walk's twin draws its slips from its own generator: each of its transitions is
// one the C++ chain makes, at the C++ chain's slip rate, and without slips the two
// are one function.

#if GGK_WITH_PYTHON

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "engine/job/job_file.hpp"
#include "engine/run/job_runner.hpp"
#include "engine/tasks/task_list.hpp"
#include "sims/chain/chain.hpp"
#include "sims/mountain_car/mountain_car.hpp"
#include "sims/pendulum/pendulum.hpp"

namespace ggk::engine {
namespace {

namespace fs = std::filesystem;

std::optional<RunRecord> ci_python_env_run(std::vector<std::string> overrides) {
  const char* source_dir = std::getenv("GGK_SOURCE_DIR");
  if (source_dir == nullptr) return std::nullopt;
  JobLoadOptions options;
  options.check_output = false;
  options.overrides = std::move(overrides);
  return compute_run(
      load_job_file(fs::path(source_dir) / "jobs/ci-python-env.toml", task_tables(), options), 0);
}

TEST(PythonEnvTwins, MountainCarSamplesReplayInTheCppSimulatorBitForBit) {
  const auto record =
      ci_python_env_run({"python_env.series=40", "python_env.kwargs.max_episode_steps=30"});
  if (!record) GTEST_SKIP() << "GGK_SOURCE_DIR is not set (run through ctest)";
  const sims::mountain_car::MountainCarConfig c;
  const auto& s = record->samples;
  ASSERT_GT(s.observations.rows(), 0);
  std::int64_t truncated_series = 0;
  for (Eigen::Index i = 0; i < s.observations.rows(); ++i) {
    const auto k = static_cast<std::size_t>(i);
    const sims::mountain_car::State next =
        sims::mountain_car::step(c, {s.observations(i, 0), s.observations(i, 1)}, s.actions[k]);
    EXPECT_EQ(next.position, s.next_observations(i, 0));
    EXPECT_EQ(next.velocity, s.next_observations(i, 1));
    EXPECT_EQ(s.terminals[k] != 0, sims::mountain_car::at_goal(c, next));
    EXPECT_EQ(s.rewards[k], -1.0);
    // A series ends at 30 steps (truncated, not absorbing) or at the goal.
    const bool last =
        i + 1 == s.observations.rows() || s.observations.row(i + 1) != s.next_observations.row(i);
    if (last && !s.terminals[k]) ++truncated_series;
  }
  // From Gymnasium's reset in the valley, 30 random pushes never reach the goal.
  EXPECT_EQ(s.observations.rows(), 40 * 30);
  EXPECT_EQ(truncated_series, 40);
}

TEST(PythonEnvTwins, PendulumWithoutNoiseReplaysInTheCppSimulatorBitForBit) {
  const auto record =
      ci_python_env_run({"python_env.factory=\"ggk_test_envs.pendulum:PendulumTwin\"",
                         "python_env.series=30", "lspi.gamma=0.95"});
  if (!record) GTEST_SKIP() << "GGK_SOURCE_DIR is not set (run through ctest)";
  sims::pendulum::PendulumConfig c;
  c.noise = 0.0;
  const auto& s = record->samples;
  ASSERT_GT(s.observations.rows(), 30);
  for (Eigen::Index i = 0; i < s.observations.rows(); ++i) {
    const auto k = static_cast<std::size_t>(i);
    const double force = (s.actions[k] - 1) * c.force;
    const sims::pendulum::State next =
        sims::pendulum::integrate(c, {s.observations(i, 0), s.observations(i, 1)}, force);
    EXPECT_EQ(next.angle, s.next_observations(i, 0)) << "sample " << i;
    EXPECT_EQ(next.velocity, s.next_observations(i, 1)) << "sample " << i;
    EXPECT_EQ(s.terminals[k] != 0, sims::pendulum::fallen(next));
  }
}

// The chain twin's samples through the python_env task: sample i moves from state
// s_i (its one-float observation) to Chain::move(s_i, a_i, intended) for one of
// the two values of `intended`, with Chain::reward of the state entered, never
// terminal; `intended` holds at the chain's success rate; with success = 1 every
// sample is exactly the C++ chain's intended move.
void check_chain_twin(double success) {
  const std::string kwargs = "python_env.kwargs.success=" + std::to_string(success);
  const auto record = ci_python_env_run(
      {"python_env.factory=\"ggk_test_envs.chain:ChainTwin\"", "python_env.series=200", kwargs});
  if (!record) GTEST_SKIP() << "GGK_SOURCE_DIR is not set (run through ctest)";
  sims::chain::ChainConfig config;
  config.success = success;
  const sims::chain::Chain chain(config);
  const auto& s = record->samples;
  ASSERT_GT(s.observations.rows(), 1000);
  std::int64_t slips = 0;
  for (Eigen::Index i = 0; i < s.observations.rows(); ++i) {
    const auto k = static_cast<std::size_t>(i);
    const auto state = static_cast<std::int32_t>(s.observations(i, 0));
    ASSERT_EQ(static_cast<double>(state), s.observations(i, 0));
    const double next = s.next_observations(i, 0);
    const bool intended = next == chain.move(state, s.actions[k], true);
    const bool slipped = next == chain.move(state, s.actions[k], false);
    ASSERT_TRUE(intended || slipped) << "sample " << i << ": " << state << " -> " << next;
    if (!intended) ++slips;
    EXPECT_EQ(s.rewards[k], chain.reward(static_cast<std::int32_t>(next)));
    EXPECT_EQ(s.terminals[k], 0);
  }
  const double n = static_cast<double>(s.observations.rows());
  const double rate = (1.0 - success);
  // Within 5 binomial standard deviations (and none at all without slips).
  EXPECT_NEAR(static_cast<double>(slips) / n, rate,
              5.0 * std::sqrt(rate * (1.0 - rate) / n) + 1e-12);
}

TEST(PythonEnvTwins, ChainWalkTransitionsAreTheCppChainsAtItsSlipRate) {
  check_chain_twin(0.9);
}

TEST(PythonEnvTwins, ChainWalkWithoutSlipsIsTheCppChain) {
  check_chain_twin(1.0);
}

}  // namespace
}  // namespace ggk::engine

#endif  // GGK_WITH_PYTHON
