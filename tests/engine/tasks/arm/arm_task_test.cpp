// A small arm job end to end (jobs/arm-quick.toml, run 0): the protocol of paper
// sec. 4.1 on the calibrated geometry.

#include "engine/tasks/arm/arm_task.hpp"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <set>
#include <string>

#include <gtest/gtest.h>

#include "engine/job/job_file.hpp"
#include "engine/run/job_runner.hpp"
#include "engine/tasks/task_list.hpp"
#include "sims/arm/arm.hpp"

namespace ggk::engine {
namespace {

double metric(const FitRecord& fit, const std::string& name) {
  for (const auto& [key, value] : fit.metrics) {
    if (key == name) return value;
  }
  ADD_FAILURE() << "no metric " << name;
  return std::nan("");
}

const NamedArray* array(const std::vector<NamedArray>& arrays, const std::string& name) {
  for (const NamedArray& a : arrays) {
    if (a.name == name) return &a;
  }
  return nullptr;
}

TEST(ArmTask, QuickJobRunsThePaperProtocol) {
  const char* source_dir = std::getenv("GGK_SOURCE_DIR");
  ASSERT_NE(source_dir, nullptr) << "ctest sets GGK_SOURCE_DIR";
  JobLoadOptions options;
  options.check_output = false;
  const JobSpec job = load_job_file(std::filesystem::path(source_dir) / "jobs" / "arm-quick.toml",
                                    task_tables(), options);
  const auto& config = task_config_as<sims::arm::ArmConfig>(job);
  const sims::arm::Arm arm(config);

  const RunRecord record = compute_run(job, 0);
  ASSERT_EQ(record.samples.actions.size(), 50u * 1000u);
  ASSERT_EQ(record.fits.size(), 4u);  // {ggk, ogk} x {16, 32} kernels
  const std::set<std::int32_t> goals(arm.goal_states().begin(), arm.goal_states().end());
  ASSERT_EQ(goals.size(), 16u);

  for (const FitRecord& fit : record.fits) {
    SCOPED_TRACE(std::string(kernel_type_name(fit.point.basis)) + " " +
                 std::to_string(fit.point.kernels));
    ASSERT_TRUE(fit.status == "converged" || fit.status == "max_iterations") << fit.message;
    EXPECT_EQ(fit.lspi.weights.size(), 4 * fit.point.kernels);
    // The walk goes through goals, so all 16 goals are graph nodes and the first centres.
    EXPECT_EQ(std::set<std::int32_t>(fit.centers.begin(), fit.centers.begin() + 16), goals);
    const double success = metric(fit, "success_from_A");
    EXPECT_TRUE(success == 0.0 || success == 1.0);
    const NamedArray* trajectory = array(fit.arrays, "trajectory_A");
    ASSERT_NE(trajectory, nullptr);
    EXPECT_EQ(trajectory->values.front(), arm.start_state_A());
    if (success == 1.0) {
      EXPECT_TRUE(goals.count(static_cast<std::int32_t>(trajectory->values.back())));
      EXPECT_EQ(metric(fit, "steps_from_A"), static_cast<double>(trajectory->values.size() - 1));
    }
    const double rate = metric(fit, "success_rate");
    EXPECT_GE(rate, 0.0);
    EXPECT_LE(rate, 1.0);
    ASSERT_NE(array(fit.arrays, "state_values"), nullptr);
    EXPECT_EQ(array(fit.arrays, "state_values")->values.size(),
              static_cast<std::size_t>(arm.num_states()));
  }
  // The joint grid for the figures: 37 x 72, state ids where the pose is free.
  const NamedArray* grid = array(record.arrays, "grid/state_of");
  ASSERT_NE(grid, nullptr);
  ASSERT_EQ(grid->shape, (std::vector<std::int64_t>{37, 72}));
  for (std::int32_t i = 0; i < 37; ++i) {
    for (std::int32_t j = 0; j < 72; ++j) {
      EXPECT_EQ(grid->values[static_cast<std::size_t>(i * 72 + j)], arm.state_of(i, j));
    }
  }
  // Within 2 % of the paper's 1605 graph nodes.
  const double nodes = metric(record.fits.front(), "graph_nodes");
  EXPECT_NEAR(nodes, 1605.0, 0.02 * 1605.0);
}

}  // namespace
}  // namespace ggk::engine
