// The Khepera simulator (sims/khepera): one control step (wheel noise, arc, body
// overlap at 4 sub-steps, 24 IR rays, 8 noisy readings), sensing alone, and the
// body overlap test, in an arena like jobs/arenas/default.toml. One thread: a
// Khepera is shared read-only, so steps/s scale with cores.
// Counters: steps (or calls) per second.

#include <benchmark/benchmark.h>

#include <cstdint>
#include <vector>

#include "kernels/random_stream.hpp"
#include "sims/khepera/khepera.hpp"

namespace ggk::bench {
namespace {

using namespace sims::khepera;

// The obstacles of jobs/arenas/default.toml (80 x 80 cm, walled).
KheperaConfig default_like_config() {
  KheperaConfig config;
  config.arena.max = {80.0, 80.0};
  config.arena.start = {21.0, 36.0, 1.5707963267948966};
  config.arena.obstacles = {Rectangle{{14.0, 50.0}, {28.0, 58.0}},
                            Rectangle{{12.0, 10.0}, {26.0, 22.0}},
                            Disc{{38.0, 18.0}, 4.0},
                            Disc{{62.0, 38.0}, 7.0},
                            RotatedRectangle{{54.0, 63.0}, 22.0, 5.0, 30.0},
                            Segment{{80.0, 18.0}, {64.0, 18.0}}};
  return config;
}

// Poses from random walks, so that benchmarks see the protocol's mix of open
// space and obstacles.
std::vector<Pose> walk_poses(const Khepera& robot, std::int32_t count) {
  kernels::RandomStream random(1, 0, 0);
  std::vector<Pose> poses;
  Pose pose = robot.sample_free_pose(random);
  while (static_cast<std::int32_t>(poses.size()) < count) {
    if (poses.size() % 100 == 0) pose = robot.sample_free_pose(random);
    const auto action = static_cast<std::int32_t>(random.uniform_index(kNumActions));
    pose = robot.step(pose, action, random).next_pose;
    poses.push_back(pose);
  }
  return poses;
}

// The sampling protocol: series of 100 random actions from random free poses.
void BM_KheperaRandomWalk(benchmark::State& state) {
  const Khepera robot(default_like_config());
  kernels::RandomStream random(2, 0, 0);
  Pose pose = robot.sample_free_pose(random);
  std::int64_t steps = 0;
  for (auto _ : state) {
    if (steps % 100 == 0) pose = robot.sample_free_pose(random);
    const auto action = static_cast<std::int32_t>(random.uniform_index(kNumActions));
    const StepResult result = robot.step(pose, action, random);
    benchmark::DoNotOptimize(result.observation.data());
    pose = result.next_pose;
    ++steps;
  }
  state.counters["steps/s"] =
      benchmark::Counter(static_cast<double>(steps), benchmark::Counter::kIsRate);
}

void BM_KheperaSense(benchmark::State& state) {
  const Khepera robot(default_like_config());
  const std::vector<Pose> poses = walk_poses(robot, 4096);
  kernels::RandomStream random(3, 0, 0);
  std::size_t i = 0;
  for (auto _ : state) {
    const Readings readings = robot.sense(poses[i++ % poses.size()], random);
    benchmark::DoNotOptimize(readings.data());
  }
  state.counters["calls/s"] =
      benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}

void BM_KheperaSenseNoiseless(benchmark::State& state) {
  const Khepera robot(default_like_config());
  const std::vector<Pose> poses = walk_poses(robot, 4096);
  std::size_t i = 0;
  for (auto _ : state) {
    const Readings readings = robot.sense_noiseless(poses[i++ % poses.size()]);
    benchmark::DoNotOptimize(readings.data());
  }
  state.counters["calls/s"] =
      benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}

void BM_KheperaCollides(benchmark::State& state) {
  const Khepera robot(default_like_config());
  const std::vector<Pose> poses = walk_poses(robot, 4096);
  std::size_t i = 0;
  for (auto _ : state) benchmark::DoNotOptimize(robot.collides(poses[i++ % poses.size()]));
  state.counters["calls/s"] =
      benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}

BENCHMARK(BM_KheperaRandomWalk);
BENCHMARK(BM_KheperaSense);
BENCHMARK(BM_KheperaSenseNoiseless);
BENCHMARK(BM_KheperaCollides);

}  // namespace
}  // namespace ggk::bench

BENCHMARK_MAIN();
