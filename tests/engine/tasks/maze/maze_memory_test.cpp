// estimate_maze_run: grows with every size of a maze job, stays finite for the
// largest walk the [maze] table accepts (issue 13, item 10), and is no less than
// what a run's record holds.

#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "engine/job/job_file.hpp"
#include "engine/run/job_runner.hpp"
#include "engine/tasks/maze/maze_task.hpp"
#include "engine/tasks/record_bytes.hpp"
#include "engine/tasks/task_list.hpp"

namespace ggk::engine {
namespace {

constexpr const char* kRoom =
    "#########\n"
    "#.......#\n"
    "#.......#\n"
    "#......G#\n"
    "#########\n";

struct MazeJob {
  std::string map = kRoom;
  std::string kernels = "[4, 8]";
  std::string solver = "[\"brm\"]";
  long long series = 5;
  long long steps = 100;
  long long runs = 1;
};

JobSpec parse(const MazeJob& m) {
  const std::string text =
      "name = \"m\"\ntask = \"maze\"\nruns = " + std::to_string(m.runs) +
      "\nseed = 3\n[sweep]\nkernels = " + m.kernels + "\nsigma = [2.0]\nsolver = " + m.solver +
      "\n[maze]\nseries = " + std::to_string(m.series) +
      "\nsteps_per_series = " + std::to_string(m.steps) + "\nmap = \"\"\"\n" + m.map + "\"\"\"\n";
  JobLoadOptions options;
  options.check_output = false;
  return parse_job(text, "memory.toml", task_tables(), options);
}

RunMemoryEstimate estimate(const MazeJob& m) {
  const JobSpec job = parse(m);
  const TaskDefinition* task = find_task("maze");
  EXPECT_NE(task->estimate_run_bytes, nullptr);
  return task->estimate_run_bytes(job);
}

// An open square room of side n with a goal in a corner.
std::string room(int n) {
  std::string map = std::string(n + 2, '#') + "\n";
  for (int r = 0; r < n; ++r) {
    map += "#" + std::string(n - 1, '.') + (r == 0 ? "G" : ".") + "#\n";
  }
  return map + std::string(n + 2, '#') + "\n";
}

TEST(MazeMemory, GrowsWithSamplesKernelsAndStates) {
  const MazeJob base;
  const double peak = estimate(base).peak(1);
  EXPECT_GT(peak, 0.0);

  MazeJob more_steps = base;
  more_steps.steps *= 10;
  EXPECT_GT(estimate(more_steps).peak(1), peak);
  MazeJob more_series = base;
  more_series.series *= 10;
  EXPECT_GT(estimate(more_series).peak(1), peak);

  MazeJob more_kernels = base;
  more_kernels.kernels = "[4, 30]";
  const RunMemoryEstimate wide = estimate(more_kernels);
  EXPECT_GT(wide.peak(1), peak);
  EXPECT_GT(wide.fit_bytes(), estimate(base).fit_bytes());

  MazeJob bigger_map = base;
  bigger_map.map = room(40);
  EXPECT_GT(estimate(bigger_map).peak(1), peak);

  // More sweep points keep more results; runs are the runner's business.
  MazeJob more_points = base;
  more_points.solver = "[\"brm\", \"lstdq\"]";
  EXPECT_GT(estimate(more_points).record_bytes, estimate(base).record_bytes);
  MazeJob more_runs = base;
  more_runs.runs = 1000;
  EXPECT_EQ(estimate(more_runs).peak(1), peak);

  // Fits in flight multiply only the per-fit part.
  EXPECT_DOUBLE_EQ(estimate(base).peak(3) - estimate(base).peak(1),
                   2.0 * estimate(base).fit_bytes());
}

TEST(MazeMemory, TheLongestWalkIsHugeAndFinite) {
  MazeJob longest;
  longest.series = 1;
  longest.steps = 2147483647;
  const RunMemoryEstimate e = estimate(longest);
  EXPECT_TRUE(std::isfinite(e.peak(1)));
  EXPECT_GT(e.peak(1), 100e9);  // over 2^31 samples of ~100 bytes in their copies
  // The samples dominate, and the item says so.
  const MemoryItem* largest = &e.items.front();
  for (const MemoryItem& item : e.items) {
    if (item.bytes > largest->bytes) largest = &item;
  }
  EXPECT_NE(largest->what.find("2147483647 samples"), std::string::npos) << largest->what;
  EXPECT_GT(largest->bytes, 100e9);
}

TEST(MazeMemory, CoversWhatARunRecordHolds) {
  MazeJob m;
  m.map = room(12);
  m.kernels = "[10, 40]";
  m.solver = "[\"brm\", \"lstdq\"]";
  const JobSpec job = parse(m);
  const RunMemoryEstimate e = find_task("maze")->estimate_run_bytes(job);
  const double held = record_bytes(compute_run(job, 0));
  EXPECT_GE(e.record_bytes, held);
  EXPECT_LT(e.record_bytes, 10.0 * held);
  EXPECT_GE(e.peak(1), e.record_bytes);
}

}  // namespace
}  // namespace ggk::engine
