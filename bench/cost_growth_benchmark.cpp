// Cost growth of one whole run (issue 14, goal 5): how the time of one run of a
// shipped job grows with the arm's joint grid (states) and with the Khepera's
// samples, everything else as the job gives it.
//
// BM_ArmRun/step_tenths:{50,25,10}: one run (run 0) of jobs/arm-paper.toml at a
// joint grid step of 5, 2.5 and 1 degree ([arm] grid_step_degrees): 37 x 72,
// 73 x 143 and 181 x 356 cells. The samples stay 50 x 1000 random moves, the
// kernel width 5 units of 5 degrees, the test step limit 100 moves (no silent
// rescaling: sims/arm/README.md). Sweep: both bases at 64 kernels, BRM.
// BM_KheperaRun/samples:{5000,20000,80000}: one run of jobs/khepera-paper.toml
// with 50, 200 and 800 series of 100 steps (the job's 200 x 100 is 20,000), the
// 24 x 29 SOM, its 30 epochs and the 10 test episodes as given; sweep: both
// bases at 60 kernels, BRM.
// BM_MazeRun/side:{250,500,1000}: one run of an open side x side maze (no walls,
// goal in a corner), 20 series of 1000 random steps, 4 GGK kernels, a 1-step
// test: the per-state work (graph, nearest visited state of every unvisited cell
// by a k-d tree, kernel tables) against states; before the k-d tree the nearest
// search was quadratic (1500 x 1500: > 300 s). Replaces a timing assertion that
// MazeProtocol.ALargeMapRuns once held.
//
// compute_run() runs in a oneTBB arena of 1 thread (run with
// OPENBLAS_NUM_THREADS=1), so that the slope is the algorithm's, not the
// machine's; Time is wall time, CPU the whole process's CPU time (steadier on a
// shared machine). Counters: states (free poses, or SOM units) and samples of
// the run; report time against them on log-log axes (the closing note of issue
// 14 quotes the slope).

#include <benchmark/benchmark.h>

#include <oneapi/tbb/task_arena.h>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "engine/job/job_file.hpp"
#include "engine/run/job_runner.hpp"
#include "engine/tasks/task_list.hpp"
#include "sims/arm/arm.hpp"

namespace ggk::bench {
namespace {

const std::filesystem::path kJobs = std::filesystem::path(GGK_SOURCE_DIR) / "jobs";

engine::JobSpec load(const std::string& file, std::vector<std::string> overrides) {
  engine::JobLoadOptions options;
  options.check_output = false;
  options.overrides = std::move(overrides);
  return engine::load_job_file(kJobs / file, engine::task_tables(), options);
}

void run_once(benchmark::State& state, const engine::JobSpec& job) {
  tbb::task_arena arena(1);
  std::int64_t samples = 0;
  for (auto _ : state) {
    const engine::RunRecord record = arena.execute([&] { return engine::compute_run(job, 0); });
    samples = static_cast<std::int64_t>(record.samples.actions.size());
    benchmark::DoNotOptimize(record.fits.data());
  }
  state.counters["samples"] = static_cast<double>(samples);
}

void BM_ArmRun(benchmark::State& state) {
  const auto tenths = static_cast<std::int32_t>(state.range(0));
  const std::string step = sims::arm::grid_step_text(tenths);
  const engine::JobSpec job =
      load("arm-paper.toml", {"runs=1", "sweep.kernels=[64]", "arm.grid_step_degrees=" + step});
  const sims::arm::Arm arm(engine::task_config_as<sims::arm::ArmConfig>(job));
  state.counters["states"] = arm.num_states();
  state.counters["cells"] = static_cast<double>(arm.shoulder_steps()) * arm.elbow_steps();
  run_once(state, job);
}
BENCHMARK(BM_ArmRun)
    ->ArgName("step_tenths")
    ->Arg(50)
    ->Arg(25)
    ->Arg(10)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MeasureProcessCPUTime()
    ->Iterations(1);

void BM_KheperaRun(benchmark::State& state) {
  const std::int64_t samples = state.range(0);
  const engine::JobSpec job =
      load("khepera-paper.toml",
           {"runs=1", "sweep.kernels=[60]", "sweep.solver=[\"brm\"]",
            "khepera.steps_per_series=100", "khepera.series=" + std::to_string(samples / 100)});
  state.counters["states"] = 24 * 29;  // SOM units, the graph's nodes
  run_once(state, job);
}
BENCHMARK(BM_KheperaRun)
    ->ArgName("samples")
    ->Arg(5000)
    ->Arg(20000)
    ->Arg(80000)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MeasureProcessCPUTime()
    ->Iterations(1);

void BM_MazeRun(benchmark::State& state) {
  const auto side = static_cast<std::size_t>(state.range(0));
  std::string map(side * (side + 1), '.');
  for (std::size_t r = 0; r < side; ++r) map[r * (side + 1) + side] = '\n';
  map[0] = 'G';
  const std::string text =
      "name = \"open\"\ntask = \"maze\"\nruns = 1\nseed = 3\n"
      "[sweep]\nbasis = [\"ggk\"]\nkernels = [4]\nsigma = [10.0]\n"
      "[maze]\nseries = 20\nsteps_per_series = 1000\ntest_max_steps = 1\nmap = \"\"\"\n" +
      map + "\"\"\"\n";
  engine::JobLoadOptions options;
  options.check_output = false;
  const engine::JobSpec job = engine::parse_job(text, "open.toml", engine::task_tables(), options);
  state.counters["states"] = static_cast<double>(side * side);
  run_once(state, job);
}
BENCHMARK(BM_MazeRun)
    ->ArgName("side")
    ->Arg(250)
    ->Arg(500)
    ->Arg(1000)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MeasureProcessCPUTime()
    ->Iterations(1);

}  // namespace
}  // namespace ggk::bench

BENCHMARK_MAIN();
