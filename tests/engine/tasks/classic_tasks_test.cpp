// The classic continuous tasks (pendulum, mountain_car, acrobot) through their
// shipped CI jobs (smaller walks): every stored sample agrees with its
// simulator (the mountain car's replayed bit for bit), the rewards and the
// terminal flags are the task's, the series start where the task says, and the
// observations are stored unscaled beside the scale that the task documents.

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <numbers>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "engine/job/job_file.hpp"
#include "engine/run/job_runner.hpp"
#include "engine/tasks/task_list.hpp"
#include "sims/acrobot/acrobot.hpp"
#include "sims/mountain_car/mountain_car.hpp"
#include "sims/pendulum/pendulum.hpp"

namespace ggk::engine {
namespace {

namespace fs = std::filesystem;

// Run 0 of jobs/<job>.toml with `overrides`, or nullopt outside ctest.
std::optional<RunRecord> shipped_run(const std::string& job, std::vector<std::string> overrides) {
  const char* source_dir = std::getenv("GGK_SOURCE_DIR");
  if (source_dir == nullptr) return std::nullopt;
  JobLoadOptions options;
  options.check_output = false;
  options.overrides = std::move(overrides);
  const JobSpec spec =
      load_job_file(fs::path(source_dir) / "jobs" / (job + ".toml"), task_tables(), options);
  return compute_run(spec, 0);
}

const NamedArray& array_named(const RunRecord& record, const std::string& name) {
  for (const NamedArray& array : record.arrays) {
    if (array.name == name) return array;
  }
  throw std::runtime_error("no array " + name);
}

// Whether sample i starts a series (its state is not the previous sample's next state).
bool starts_series(const RunRecord& r, Eigen::Index i) {
  return i == 0 || r.samples.observations.row(i) != r.samples.next_observations.row(i - 1) ||
         r.samples.terminals[static_cast<std::size_t>(i - 1)] != 0;
}

TEST(ClassicTasks, MountainCarSamplesReplayBitForBit) {
  const auto record = shipped_run("ci-mountain-car", {"mountain_car.series=30"});
  if (!record) GTEST_SKIP() << "GGK_SOURCE_DIR is not set (run through ctest)";
  const sims::mountain_car::MountainCarConfig c;
  const auto& s = record->samples;
  std::int64_t terminals = 0;
  for (Eigen::Index i = 0; i < s.observations.rows(); ++i) {
    const auto k = static_cast<std::size_t>(i);
    const sims::mountain_car::State next =
        sims::mountain_car::step(c, {s.observations(i, 0), s.observations(i, 1)}, s.actions[k]);
    EXPECT_EQ(next.position, s.next_observations(i, 0));
    EXPECT_EQ(next.velocity, s.next_observations(i, 1));
    EXPECT_EQ(s.rewards[k], -1.0);
    EXPECT_EQ(s.terminals[k] != 0, sims::mountain_car::at_goal(c, next));
    terminals += s.terminals[k];
    if (starts_series(*record, i)) {  // the state box
      EXPECT_GE(s.observations(i, 0), -1.2);
      EXPECT_LT(s.observations(i, 0), 0.5);
      EXPECT_LE(std::abs(s.observations(i, 1)), 0.07);
    }
  }
  EXPECT_GT(terminals, 0);
  EXPECT_EQ(array_named(*record, "observation_scale").values, (std::vector<double>{1.8, 0.14}));
  EXPECT_EQ(record->action_names, (std::vector<std::string>{"push_left", "no_push", "push_right"}));
}

TEST(ClassicTasks, PendulumEpisodesEndWhenThePoleFalls) {
  const auto record = shipped_run("ci-pendulum", {"pendulum.series=60"});
  if (!record) GTEST_SKIP() << "GGK_SOURCE_DIR is not set (run through ctest)";
  const auto& s = record->samples;
  std::int64_t series = 0;
  for (Eigen::Index i = 0; i < s.observations.rows(); ++i) {
    const auto k = static_cast<std::size_t>(i);
    const sims::pendulum::State next{s.next_observations(i, 0), s.next_observations(i, 1)};
    EXPECT_EQ(s.terminals[k] != 0, sims::pendulum::fallen(next));
    EXPECT_EQ(s.rewards[k], s.terminals[k] ? -1.0 : 0.0);
    EXPECT_LT(std::abs(s.observations(i, 0)), std::numbers::pi / 2);  // never after a fall
    if (starts_series(*record, i)) {
      ++series;  // near upright
      EXPECT_LE(std::abs(s.observations(i, 0)), 0.1);
      EXPECT_LE(std::abs(s.observations(i, 1)), 0.1);
    }
  }
  EXPECT_EQ(series, 60);
  const std::vector<double> scale = array_named(*record, "observation_scale").values;
  EXPECT_EQ(scale[0], std::numbers::pi);
  EXPECT_NEAR(scale[1], 2.0 * std::sqrt(1.5 * 9.8 / 0.5), 1e-12);
}

TEST(ClassicTasks, AcrobotObservationsAreGymnasiums) {
  const auto record = shipped_run("ci-acrobot", {"acrobot.series=20"});
  if (!record) GTEST_SKIP() << "GGK_SOURCE_DIR is not set (run through ctest)";
  const auto& s = record->samples;
  ASSERT_EQ(s.observations.cols(), 6);
  for (Eigen::Index i = 0; i < s.observations.rows(); ++i) {
    const auto k = static_cast<std::size_t>(i);
    const auto o = s.next_observations.row(i);
    EXPECT_NEAR(o(0) * o(0) + o(1) * o(1), 1.0, 1e-15);
    EXPECT_NEAR(o(2) * o(2) + o(3) * o(3), 1.0, 1e-15);
    EXPECT_LE(std::abs(o(4)), sims::acrobot::kMaxVelocity1);
    EXPECT_LE(std::abs(o(5)), sims::acrobot::kMaxVelocity2);
    EXPECT_EQ(s.rewards[k], s.terminals[k] ? 0.0 : -1.0);
    // -cos(t1) - cos(t1 + t2) = -c1 - (c1 c2 - s1 s2): away from the edge the flag is exact.
    const double height = -o(0) - (o(0) * o(2) - o(1) * o(3));
    if (std::abs(height - 1.0) > 1e-9) {
      EXPECT_EQ(s.terminals[k] != 0, height > 1.0);
    }
  }
}

}  // namespace
}  // namespace ggk::engine
