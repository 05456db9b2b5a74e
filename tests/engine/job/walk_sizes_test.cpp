// read_walk_sizes (engine/job/walk_sizes.hpp): defaults, the keys, and the
// 32-bit limit on a run's samples or readings, reported at steps_per_series.

#include "engine/job/walk_sizes.hpp"

#include <array>
#include <string>
#include <string_view>

#include <gtest/gtest.h>
#include <toml++/toml.h>

#include "engine/job/job_error.hpp"

namespace ggk::engine {
namespace {

constexpr std::array<std::string_view, 2> kWalkKeys = {"series", "steps_per_series"};

// The JobError message of reading `text` as the table [walk], or "ok".
std::string outcome(const std::string& text, WalkIds ids, WalkSizes* sizes = nullptr) {
  const toml::table table = toml::parse(text);
  const TomlTableReader reader(table, "walk", "w.toml", kWalkKeys);
  try {
    const WalkSizes read = read_walk_sizes(reader, {3, 7}, ids);
    if (sizes != nullptr) *sizes = read;
  } catch (const JobError& error) {
    return error.what();
  }
  return "ok";
}

TEST(WalkSizes, DefaultsAndKeys) {
  WalkSizes sizes;
  EXPECT_EQ(outcome("", WalkIds::kSamples, &sizes), "ok");
  EXPECT_EQ(sizes.series, 3);
  EXPECT_EQ(sizes.steps_per_series, 7);
  EXPECT_EQ(outcome("series = 10\nsteps_per_series = 20\n", WalkIds::kSamples, &sizes), "ok");
  EXPECT_EQ(sizes.series, 10);
  EXPECT_EQ(sizes.steps_per_series, 20);
  EXPECT_NE(outcome("series = 0\n", WalkIds::kSamples).find("series"), std::string::npos);
}

TEST(WalkSizes, RunIdsMustFit32Bits) {
  // 46341 x 46341 = 2147488281 samples: one past the limit's square root.
  const std::string square = "series = 46341\nsteps_per_series = 46341\n";
  const std::string samples = outcome(square, WalkIds::kSamples);
  EXPECT_NE(samples.find("steps_per_series"), std::string::npos) << samples;
  EXPECT_NE(samples.find("series x steps_per_series = 2147488281 samples per run"),
            std::string::npos)
      << samples;
  // 2 x 1073741823 samples fit; their 2 x 1073741824 readings do not.
  const std::string half = "series = 2\nsteps_per_series = 1073741823\n";
  EXPECT_EQ(outcome(half, WalkIds::kSamples), "ok");
  EXPECT_NE(outcome(half, WalkIds::kReadings)
                .find("series x (steps_per_series + 1) = 2147483648 readings per run"),
            std::string::npos);
}

}  // namespace
}  // namespace ggk::engine
