// One run of each paper job as the job gives it (all its bases, kernel counts and
// solvers), with the floating-point operations its BLAS and LAPACK work counts
// (kernels/flop_count.hpp) and what they would take at the single-core dgemm
// peak: the "measured / bound" rows of bench/README.md's limit analysis.
//
// BM_PaperRun/job:0 is run 0 of jobs/arm-paper.toml, job:1 run 0 of
// jobs/khepera-paper.toml. compute_run() runs in a oneTBB arena of 1 thread (run
// with OPENBLAS_NUM_THREADS=1); Time is wall time, CPU the whole process's.
// Counters: GFlop (counted per run), GFlops (their rate over the run's wall time),
// and bound_s (the counted flops at the GGK_PEAK_GFLOPS rate, default 52.4: this
// machine's BM_DgemmPeak in lspi_benchmark), so that measured / bound = Time /
// bound_s.
//
//   OPENBLAS_NUM_THREADS=1 build/bench/paper_run_benchmark --benchmark_repetitions=3
//       --benchmark_report_aggregates_only=true   (one line)

#include <benchmark/benchmark.h>

#include <oneapi/tbb/task_arena.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "engine/job/job_file.hpp"
#include "engine/run/job_runner.hpp"
#include "engine/tasks/task_list.hpp"
#include "kernels/flop_count.hpp"

namespace ggk::bench {
namespace {

const std::filesystem::path kJobs = std::filesystem::path(GGK_SOURCE_DIR) / "jobs";

// The single-core dgemm peak, GFlop/s: GGK_PEAK_GFLOPS, else this machine's.
double peak_gflops() {
  const char* text = std::getenv("GGK_PEAK_GFLOPS");
  return text != nullptr ? std::atof(text) : 52.4;
}

void BM_PaperRun(benchmark::State& state) {
  const char* file = state.range(0) == 0 ? "arm-paper.toml" : "khepera-paper.toml";
  engine::JobLoadOptions options;
  options.check_output = false;
  options.overrides = {"runs=1"};
  const engine::JobSpec job = engine::load_job_file(kJobs / file, engine::task_tables(), options);
  tbb::task_arena arena(1);
  double flops = 0.0;
  for (auto _ : state) {
    const double before = kernels::flops_counted();
    const engine::RunRecord record = arena.execute([&] { return engine::compute_run(job, 0); });
    flops = kernels::flops_counted() - before;
    benchmark::DoNotOptimize(record.fits.data());
  }
  state.counters["GFlop"] = flops / 1e9;
  state.counters["GFlops"] =
      benchmark::Counter(flops / 1e9, benchmark::Counter::kIsIterationInvariantRate);
  state.counters["bound_s"] = flops / 1e9 / peak_gflops();
}
BENCHMARK(BM_PaperRun)->ArgName("job")->Arg(0)->Arg(1)->Unit(benchmark::kSecond)->UseRealTime();

}  // namespace
}  // namespace ggk::bench

BENCHMARK_MAIN();
