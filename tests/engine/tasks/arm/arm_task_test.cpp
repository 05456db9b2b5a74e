// A small arm job end to end (jobs/arm-quick.toml, run 0): the protocol of paper
// sec. 4.1 on the calibrated geometry.

#include "engine/tasks/arm/arm_task.hpp"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "engine/job/job_file.hpp"
#include "engine/run/job_runner.hpp"
#include "engine/tasks/task_list.hpp"
#include "kernels/graph_diagnostics.hpp"
#include "kernels/shortest_paths.hpp"
#include "sims/arm/arm.hpp"
#include "sims/arm/kinematics.hpp"

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

// arm-quick.toml on a 2.5-degree grid ([arm] grid_step_degrees): the stored grid
// is the 73 x 143 one, every sample moves one joint by one step (0.5 state-vector
// units of 5 degrees) in the action's direction or stays, and the goal poses are
// on the 2.5-degree grid.
TEST(ArmTask, FinerGridRunsOnItsOwnGrid) {
  const char* source_dir = std::getenv("GGK_SOURCE_DIR");
  ASSERT_NE(source_dir, nullptr) << "ctest sets GGK_SOURCE_DIR";
  JobLoadOptions options;
  options.check_output = false;
  options.overrides = {"arm.grid_step_degrees=2.5", "arm.steps_per_series=200"};
  const JobSpec job = load_job_file(std::filesystem::path(source_dir) / "jobs" / "arm-quick.toml",
                                    task_tables(), options);
  const auto& config = task_config_as<sims::arm::ArmConfig>(job);
  ASSERT_EQ(config.grid_step_tenths, 25);
  const sims::arm::Arm arm(config);
  const RunRecord record = compute_run(job, 0);

  const NamedArray* grid = array(record.arrays, "grid/state_of");
  ASSERT_NE(grid, nullptr);
  ASSERT_EQ(grid->shape, (std::vector<std::int64_t>{73, 143}));
  for (std::int32_t i = 0; i < 73; ++i) {
    for (std::int32_t j = 0; j < 143; ++j) {
      ASSERT_EQ(grid->values[static_cast<std::size_t>(i * 143 + j)], arm.state_of(i, j));
    }
  }
  // Action a moves coordinate a / 2 by +0.5 (even a) or -0.5 (odd a), or not at all.
  const SampleRecord& samples = record.samples;
  ASSERT_EQ(samples.actions.size(), 50u * 200u);
  std::size_t moved = 0;
  for (std::size_t n = 0; n < samples.actions.size(); ++n) {
    const auto row = static_cast<Eigen::Index>(n);
    const std::int32_t a = samples.actions[n];
    const Eigen::Index joint = a / 2;
    const double delta = samples.next_observations(row, joint) - samples.observations(row, joint);
    ASSERT_EQ(samples.next_observations(row, 1 - joint), samples.observations(row, 1 - joint));
    ASSERT_TRUE(delta == 0.0 || delta == (a % 2 == 0 ? 0.5 : -0.5)) << n << ": " << delta;
    moved += delta != 0.0;
  }
  EXPECT_GT(moved, samples.actions.size() / 2);
  // Goal poses: whole multiples of 2.5 degrees, more of them than the 16 at 5 degrees.
  const NamedArray* goal_angles = array(record.arrays, "workspace/goal_poses_deg");
  ASSERT_NE(goal_angles, nullptr);
  EXPECT_GT(goal_angles->shape[0], 16);
  bool off_the_coarse_grid = false;
  for (const double angle : goal_angles->values) {
    EXPECT_EQ(std::fmod(angle, 2.5), 0.0) << angle;
    off_the_coarse_grid = off_the_coarse_grid || std::fmod(angle, 5.0) != 0.0;
  }
  EXPECT_TRUE(off_the_coarse_grid);
}

// The graph diagnostics of every fit (issue 11), recomputed from the stored run:
// the graph's edges and degrees, the stretch over the run's first 100 centres,
// and the kernel gap by brute force from Dijkstra's distances and Eqs. (7), (8).
// And the workspace arrays of Fig. 1(a).
TEST(ArmTask, DiagnosticsAndWorkspaceMatchTheStoredRun) {
  const char* source_dir = std::getenv("GGK_SOURCE_DIR");
  ASSERT_NE(source_dir, nullptr) << "ctest sets GGK_SOURCE_DIR";
  JobLoadOptions options;
  options.check_output = false;
  const JobSpec job = load_job_file(std::filesystem::path(source_dir) / "jobs" / "arm-quick.toml",
                                    task_tables(), options);
  const auto& config = task_config_as<sims::arm::ArmConfig>(job);
  const sims::arm::Arm arm(config);
  const RunRecord record = compute_run(job, 0);

  const NamedArray* visited_array = array(record.arrays, "graph/visited");
  ASSERT_NE(visited_array, nullptr);
  std::vector<std::uint8_t> visited;
  std::vector<std::int32_t> visited_states;
  for (std::size_t s = 0; s < visited_array->values.size(); ++s) {
    visited.push_back(visited_array->values[s] != 0.0 ? 1 : 0);
    if (visited.back()) visited_states.push_back(static_cast<std::int32_t>(s));
  }
  // Edges by hand: every stored arc u -> v with u < v (the graph is undirected).
  std::int64_t edges = 0;
  for (std::int32_t u = 0; u < record.graph.num_nodes; ++u) {
    for (std::int32_t v : record.graph.neighbors(u)) edges += u < v;
  }
  // The stretch is the graph's, between its first 100 centres whatever the job
  // sweeps: the centres of a fit of min(100, nodes) kernels of the same run.
  JobSpec wide = job;
  wide.sweep.kernels = {
      std::min(100, static_cast<std::int32_t>(metric(record.fits.front(), "graph_nodes")))};
  const RunRecord wide_record = compute_run(wide, 0);
  const std::vector<std::int32_t>& first_centers = wide_record.fits.front().centers;
  ASSERT_EQ(first_centers.size(), static_cast<std::size_t>(wide.sweep.kernels.front()));
  const double stretch = kernels::geodesic_stretch(
      kernels::geodesic_distances(record.graph, first_centers), first_centers, record.node_states);
  EXPECT_GT(stretch, 1.0);  // the obstacles make some paths longer than lines
  EXPECT_EQ(metric(wide_record.fits.front(), "geodesic_stretch"), stretch);

  for (const FitRecord& fit : record.fits) {
    SCOPED_TRACE(std::string(kernel_type_name(fit.point.basis)) + " " +
                 std::to_string(fit.point.kernels));
    EXPECT_EQ(metric(fit, "edges"), static_cast<double>(edges));
    EXPECT_EQ(metric(fit, "median_degree"), kernels::median_degree(record.graph, visited));
    EXPECT_EQ(metric(fit, "geodesic_stretch"), stretch);
    const kernels::RowMatrixXd sp = kernels::geodesic_distances(record.graph, fit.centers);
    const double two_sigma2 = 2.0 * fit.point.sigma * fit.point.sigma;
    double sum = 0.0;
    for (std::size_t j = 0; j < fit.centers.size(); ++j) {
      for (std::int32_t s : visited_states) {
        const double g = sp(static_cast<Eigen::Index>(j), s);
        const double e =
            (record.node_states.row(s) - record.node_states.row(fit.centers[j])).norm();
        const double k_ggk = std::isinf(g) ? 0.0 : std::exp(-g * g / two_sigma2);
        sum += std::abs(k_ggk - std::exp(-e * e / two_sigma2));
      }
    }
    const double gap = sum / static_cast<double>(fit.centers.size() * visited_states.size());
    EXPECT_NEAR(metric(fit, "kernel_gap"), gap, 1e-12 * std::max(gap, 1.0));
    EXPECT_GT(gap, 0.0);
  }

  // Fig. 1(a): A's end effector and every goal pose's, by forward kinematics.
  const NamedArray* pose_a = array(record.arrays, "workspace/pose_A");
  ASSERT_NE(pose_a, nullptr);
  const sims::arm::ArmPose a = sims::arm::forward_kinematics(
      config.geometry, config.start_A.shoulder_deg, config.start_A.elbow_deg);
  EXPECT_EQ(pose_a->values, (std::vector<double>{a.base.x, a.base.y, a.elbow.x, a.elbow.y,
                                                 a.end_effector.x, a.end_effector.y}));
  const NamedArray* goals = array(record.arrays, "workspace/goal_poses");
  ASSERT_NE(goals, nullptr);
  ASSERT_EQ(goals->shape, (std::vector<std::int64_t>{16, 6}));
  const sims::Disc& object = config.geometry.object;
  for (std::size_t g = 0; g < 16; ++g) {
    const double dx = goals->values[6 * g + 4] - object.center.x;
    const double dy = goals->values[6 * g + 5] - object.center.y;
    EXPECT_LE(std::hypot(dx, dy), object.radius + 1e-12) << "goal " << g;
  }
  const NamedArray* rectangles = array(record.arrays, "workspace/rectangles");
  const NamedArray* discs = array(record.arrays, "workspace/discs");
  ASSERT_NE(rectangles, nullptr);
  ASSERT_NE(discs, nullptr);
  EXPECT_EQ(rectangles->shape[0] + discs->shape[0],
            static_cast<std::int64_t>(config.geometry.obstacles.size()));
}

}  // namespace
}  // namespace ggk::engine
