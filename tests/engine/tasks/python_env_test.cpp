// The python_env task (engine/tasks/python_env/) against the C++ simulators:
// the project's Python twins (tests/python/envs/ggk_test_envs) compute the same
// dynamics operation for operation, so every sample they make through ggk
// replays bit for bit in sims/mountain_car and sims/pendulum; the task's series
// end at `terminated` (absorbing) and at `truncated` (not absorbing).

#if GGK_WITH_PYTHON

#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "engine/job/job_file.hpp"
#include "engine/run/job_runner.hpp"
#include "engine/tasks/task_list.hpp"
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

}  // namespace
}  // namespace ggk::engine

#endif  // GGK_WITH_PYTHON
