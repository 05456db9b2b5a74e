// Self-organising map at the paper's Khepera scale (sec. 4.2): 20,000 8-D
// IR-like readings in [0, 1023] (30 clusters, each with some sensors at 0, noise
// sd 20, clamped), a 24 x 29 = 696-unit map.
// Cases: batch training (30 epochs, linear initialisation: 31 BMU passes over the
// samples), and one batch BMU search of the 20,000 samples; 1 and 2 threads.
// Counter: sample-to-unit distances per second.

#include <algorithm>

#include <benchmark/benchmark.h>
#include <tbb/task_arena.h>

#include "kernels/random_stream.hpp"
#include "kernels/self_organizing_map.hpp"

namespace ggk::bench {
namespace {

constexpr std::int32_t kSamples = 20000;
constexpr std::int32_t kSensors = 8;
constexpr std::int32_t kRows = 24;
constexpr std::int32_t kCols = 29;
constexpr std::int32_t kEpochs = 30;

kernels::RowMatrixXd ir_like_readings() {
  kernels::RandomStream rng(42, 0, 0);
  constexpr std::int32_t kClusters = 30;
  kernels::RowMatrixXd centres(kClusters, kSensors);
  for (Eigen::Index i = 0; i < centres.size(); ++i)
    centres.data()[i] = rng.bernoulli(0.4) ? rng.uniform(0.0, 1023.0) : 0.0;
  kernels::RowMatrixXd readings(kSamples, kSensors);
  for (std::int32_t i = 0; i < kSamples; ++i) {
    const auto c = static_cast<Eigen::Index>(rng.uniform_index(kClusters));
    for (std::int32_t j = 0; j < kSensors; ++j) {
      const double centre = centres(c, j);
      readings(i, j) = centre > 0.0 ? std::clamp(centre + 20.0 * rng.normal(), 0.0, 1023.0) : 0.0;
    }
  }
  return readings;
}

kernels::SomOptions paper_options() {
  kernels::SomOptions options;
  options.rows = kRows;
  options.cols = kCols;
  options.epochs = kEpochs;
  return options;
}

void BM_TrainSom(benchmark::State& state) {
  const auto threads = static_cast<int>(state.range(0));
  const kernels::RowMatrixXd readings = ir_like_readings();
  tbb::task_arena arena(threads);
  for (auto _ : state) {
    arena.execute([&] {
      const kernels::SelfOrganizingMap map =
          kernels::train_self_organizing_map(readings, paper_options());
      benchmark::DoNotOptimize(map.prototypes().data());
    });
  }
  state.counters["dist/s"] = benchmark::Counter(double{kSamples} * kRows * kCols * (kEpochs + 1),
                                                benchmark::Counter::kIsIterationInvariantRate);
}

void BM_BestMatchingUnits(benchmark::State& state) {
  const auto threads = static_cast<int>(state.range(0));
  const kernels::RowMatrixXd readings = ir_like_readings();
  kernels::SomOptions options = paper_options();
  options.epochs = 5;
  const kernels::SelfOrganizingMap map = kernels::train_self_organizing_map(readings, options);
  tbb::task_arena arena(threads);
  for (auto _ : state) {
    kernels::BestMatches matches;
    arena.execute([&] { matches = map.best_matching_units(readings); });
    benchmark::DoNotOptimize(matches.units.data());
  }
  state.counters["dist/s"] = benchmark::Counter(double{kSamples} * kRows * kCols,
                                                benchmark::Counter::kIsIterationInvariantRate);
}

BENCHMARK(BM_TrainSom)
    ->ArgName("threads")
    ->Arg(1)
    ->Arg(2)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_BestMatchingUnits)
    ->ArgName("threads")
    ->Arg(1)
    ->Arg(2)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace
}  // namespace ggk::bench

BENCHMARK_MAIN();
