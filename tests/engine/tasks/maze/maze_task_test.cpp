// The maze task (engine/tasks/maze/maze_task.hpp) end to end, against the claim
// of the GGK papers on their artificial tasks, on this engine's default
// maze: at equal (small) kernel count, LSPI with geodesic Gaussian kernels reaches
// the goal from more cells than with ordinary Gaussian kernels, averaged over runs.
// GGK uses its calibrated width (jobs/maze-calibration.toml); OGK is given both
// its best width there (5) and the same width (10). If this fails, the numbers
// have changed: report them, do not tune the test.

#include "engine/tasks/maze/maze_task.hpp"

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <string>
#include <tuple>

#include <gtest/gtest.h>

#include "engine/job/job_file.hpp"
#include "engine/run/job_runner.hpp"
#include "engine/tasks/task_list.hpp"

namespace ggk::engine {
namespace {

TEST(MazeClaim, GeodesicKernelsBeatOrdinaryKernelsAtSmallKernelCounts) {
  const char* source_dir = std::getenv("GGK_SOURCE_DIR");
  ASSERT_NE(source_dir, nullptr) << "ctest sets GGK_SOURCE_DIR";
  const std::filesystem::path jobs = std::filesystem::path(source_dir) / "jobs";
  const std::string text = R"(
name = "maze-claim"
task = "maze"
runs = 8
seed = 777
[sweep]
basis = ["ggk", "ogk"]
kernels = [8, 16]
sigma = [5.0, 10.0]
solver = ["brm"]
lambda = [1e-6]
[maze]
map_file = "maps/four-rooms.txt"
series = 20
steps_per_series = 500
test_max_steps = 100
)";
  JobLoadOptions options;
  options.check_output = false;
  const JobSpec job = parse_job(text, jobs / "maze-claim.toml", task_tables(), options);

  // mean success rate per (basis, kernels, sigma)
  std::map<std::tuple<std::string, std::int32_t, double>, double> mean;
  for (std::int32_t run = 0; run < job.runs; ++run) {
    const RunRecord record = compute_run(job, run);
    for (const FitRecord& fit : record.fits) {
      ASSERT_EQ(fit.metrics.front().first, "success_rate");
      mean[{std::string(kernel_type_name(fit.point.basis)), fit.point.kernels, fit.point.sigma}] +=
          fit.metrics.front().second / job.runs;
    }
  }
  for (std::int32_t kernels : {8, 16}) {
    const double ggk = mean[{"ggk", kernels, 10.0}];
    for (double ogk_sigma : {5.0, 10.0}) {
      const double ogk = mean[{"ogk", kernels, ogk_sigma}];
      EXPECT_GT(ggk, ogk) << kernels << " kernels: GGK (sigma 10) " << ggk << " vs OGK (sigma "
                          << ogk_sigma << ") " << ogk;
    }
    std::printf("%d kernels: GGK %.3f, OGK sigma 5 %.3f, OGK sigma 10 %.3f\n", kernels, ggk,
                mean[{"ogk", kernels, 5.0}], mean[{"ogk", kernels, 10.0}]);
  }
}

}  // namespace
}  // namespace ggk::engine
