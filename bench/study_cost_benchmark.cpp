// What a study's shared stages save (issue 20, item 8): one unit of a study
// with a fit-level axis of N values (its samples, SOM, graph and distances
// computed once, then N fits per sweep point) against the N single jobs that
// compute the same fits (each its own samples and graph).
//
// BM_StudyUnit/values:N: compute_unit of run 0 of jobs/khepera-paper.toml
// with "lspi.gamma" = N values (0.9, 0.85, 0.8, 0.75: fits of like cost), the
// paper's run size (200 x 100 steps, the 24 x 29 SOM), both bases at 60
// kernels, BRM, 10 test episodes.
// BM_SeparateJobs/values:N: compute_run of run 0 of the N jobs with
// --set lspi.gamma=V, one after the other: what N separate jobs compute.
// The ratio SeparateJobs / StudyUnit at the same N is the saving (one run of
// the Khepera costs mostly its samples and SOM, so it approaches N).
//
// One thread (a oneTBB arena of 1; run with OPENBLAS_NUM_THREADS=1); Time is
// wall time, CPU the process's. Both sides produce the same fits: the study's
// variant v equals job v's fits bit for bit (tests/engine/run/study_test.sh).

#include <benchmark/benchmark.h>

#include <oneapi/tbb/task_arena.h>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "engine/job/job_file.hpp"
#include "engine/job/study.hpp"
#include "engine/run/job_runner.hpp"
#include "engine/tasks/task_list.hpp"

namespace ggk::bench {
namespace {

const std::filesystem::path kJob =
    std::filesystem::path(GGK_SOURCE_DIR) / "jobs/khepera-paper.toml";
const std::vector<std::string> kGammas = {"0.9", "0.85", "0.8", "0.75"};

engine::JobLoadOptions options(std::vector<std::string> overrides,
                               std::vector<std::string> sweeps = {}) {
  engine::JobLoadOptions load;
  load.check_output = false;
  load.overrides = {"runs=1", "sweep.kernels=[60]", "sweep.solver=[\"brm\"]"};
  load.overrides.insert(load.overrides.end(), overrides.begin(), overrides.end());
  load.sweeps = std::move(sweeps);
  return load;
}

std::string gamma_values(std::size_t n) {
  std::string values;
  for (std::size_t i = 0; i < n; ++i) values += (i == 0 ? "" : ",") + kGammas[i];
  return values;
}

void BM_StudyUnit(benchmark::State& state) {
  const auto n = static_cast<std::size_t>(state.range(0));
  const engine::Study study = engine::load_study(kJob, engine::task_tables(),
                                                 options({}, {"lspi.gamma=" + gamma_values(n)}));
  tbb::task_arena arena(1);
  std::size_t fits = 0;
  for (auto _ : state) {
    const engine::RunRecord record = arena.execute([&] {
      return engine::compute_unit(study, {0, 0});
    });
    fits = record.fits.size();
    benchmark::DoNotOptimize(record.fits.data());
  }
  state.counters["fits"] = static_cast<double>(fits);
}
BENCHMARK(BM_StudyUnit)
    ->ArgName("values")
    ->Arg(1)
    ->Arg(2)
    ->Arg(4)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MeasureProcessCPUTime()
    ->Iterations(1);

void BM_SeparateJobs(benchmark::State& state) {
  const auto n = static_cast<std::size_t>(state.range(0));
  std::vector<engine::JobSpec> jobs;
  for (std::size_t i = 0; i < n; ++i) {
    jobs.push_back(
        engine::load_job_file(kJob, engine::task_tables(), options({"lspi.gamma=" + kGammas[i]})));
  }
  tbb::task_arena arena(1);
  std::size_t fits = 0;
  for (auto _ : state) {
    fits = 0;
    for (const engine::JobSpec& job : jobs) {
      const engine::RunRecord record = arena.execute([&] { return engine::compute_run(job, 0); });
      fits += record.fits.size();
      benchmark::DoNotOptimize(record.fits.data());
    }
  }
  state.counters["fits"] = static_cast<double>(fits);
}
BENCHMARK(BM_SeparateJobs)
    ->ArgName("values")
    ->Arg(1)
    ->Arg(2)
    ->Arg(4)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MeasureProcessCPUTime()
    ->Iterations(1);

}  // namespace
}  // namespace ggk::bench

BENCHMARK_MAIN();
