// estimate_arm_run: grows with the walk, the kernels and the test length, stays
// finite for the largest values the [arm] table accepts (issue 13, item 10), and
// is no less than what a run's record holds (jobs/arm-quick.toml), at the
// default joint grid and a finer one.

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <gtest/gtest.h>

#include "engine/job/job_file.hpp"
#include "engine/run/job_runner.hpp"
#include "engine/tasks/arm/arm_task.hpp"
#include "engine/tasks/record_bytes.hpp"
#include "engine/tasks/task_list.hpp"

namespace ggk::engine {
namespace {

namespace fs = std::filesystem;

fs::path quick_job() {
  const char* source_dir = std::getenv("GGK_SOURCE_DIR");
  if (source_dir == nullptr) return {};
  return fs::path(source_dir) / "jobs" / "arm-quick.toml";
}

// jobs/arm-quick.toml with `key = value` lines replaced (the key's first line).
JobSpec quick_with(const std::vector<std::pair<std::string, std::string>>& changes) {
  std::ifstream in(quick_job());
  std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  for (const auto& [key, value] : changes) {
    const std::size_t at = text.find("\n" + key + " = ");
    EXPECT_NE(at, std::string::npos) << key;
    const std::size_t end = text.find('\n', at + 1);
    text.replace(at + 1, end - at - 1, key + " = " + value);
  }
  JobLoadOptions options;
  options.check_output = false;
  return parse_job(text, quick_job(), task_tables(), options);
}

RunMemoryEstimate estimate(const std::vector<std::pair<std::string, std::string>>& changes) {
  return find_task("arm")->estimate_run_bytes(quick_with(changes));
}

class ArmMemory : public ::testing::Test {
 protected:
  void SetUp() override {
    if (quick_job().empty()) GTEST_SKIP() << "GGK_SOURCE_DIR is not set (run through ctest)";
  }
};

TEST_F(ArmMemory, GrowsWithTheWalkKernelsAndTests) {
  const double peak = estimate({}).peak(1);
  EXPECT_GT(peak, 0.0);
  EXPECT_GT(estimate({{"steps_per_series", "5000"}}).peak(1), peak);
  EXPECT_GT(estimate({{"series", "200"}}).peak(1), peak);
  EXPECT_GT(estimate({{"kernels", "[16, 300]"}}).peak(1), peak);
  EXPECT_GT(estimate({{"kernels", "[16, 300]"}}).fit_bytes(), estimate({}).fit_bytes());
  // Trajectories from A: up to test_max_steps + 1 states per fit.
  EXPECT_GT(estimate({{"test_max_steps", "100000"}}).record_bytes, estimate({}).record_bytes);
}

// arm-quick.toml's [arm] with a grid step (a key the file does not set).
std::pair<std::string, std::string> grid_step(const std::string& degrees) {
  return {"test_max_steps", "100\ngrid_step_degrees = " + degrees};
}

TEST_F(ArmMemory, GrowsWithTheJointGrid) {
  const RunMemoryEstimate five = estimate({grid_step("5")});
  EXPECT_EQ(five.peak(1), estimate({}).peak(1));
  const RunMemoryEstimate fine = estimate({grid_step("2.5")});
  const RunMemoryEstimate finer = estimate({grid_step("1")});
  EXPECT_GT(fine.peak(1), five.peak(1));
  EXPECT_GT(finer.peak(1), fine.peak(1));
  EXPECT_GT(finer.record_bytes, fine.record_bytes);
}

TEST_F(ArmMemory, TheLargestValuesAreHugeAndFinite) {
  const RunMemoryEstimate walk = estimate({{"series", "1"}, {"steps_per_series", "2147483647"}});
  EXPECT_TRUE(std::isfinite(walk.peak(1)));
  EXPECT_GT(walk.peak(1), 100e9);
  // A greedy policy that never reaches the goal walks test_max_steps steps (at
  // most 10^6, the key's range).
  const RunMemoryEstimate tests = estimate({{"test_max_steps", "1000000"}});
  EXPECT_TRUE(std::isfinite(tests.record_bytes));
  EXPECT_GT(tests.record_bytes, 4 * 1e6 * 8.0);  // 4 fits, a double per step
}

TEST_F(ArmMemory, CoversWhatARunRecordHolds) {
  const JobSpec job = quick_with({{"steps_per_series", "200"}});
  const RunMemoryEstimate e = find_task("arm")->estimate_run_bytes(job);
  const double held = record_bytes(compute_run(job, 0));
  EXPECT_GE(e.record_bytes, held);
  EXPECT_LT(e.record_bytes, 10.0 * held);
}

TEST_F(ArmMemory, CoversWhatARunRecordHoldsOnAFinerGrid) {
  const JobSpec job = quick_with({{"steps_per_series", "200"}, grid_step("2.5")});
  const RunMemoryEstimate e = find_task("arm")->estimate_run_bytes(job);
  const double held = record_bytes(compute_run(job, 0));
  EXPECT_GE(e.record_bytes, held);
  EXPECT_LT(e.record_bytes, 10.0 * held);
}

}  // namespace
}  // namespace ggk::engine
