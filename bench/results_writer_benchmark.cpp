// The writer thread's work for one run (bench/README.md, "Speed, third round",
// levers 5 and 6): run 0 of jobs/khepera-paper.toml with the paper's two bases (40
// fits, about 830 datasets), computed once, then:
//
// BM_StageRun: the run staged into a fresh in-memory HDF5 file per iteration
// (engine/store/run_store.hpp, stage_run: the same HDF5 calls as on disk without
// the disk): its datasets written and compressed, described (dims, units,
// description per dataset), and its digest read back.
// BM_RunDigest/held_open:{0,1}: the digest of the staged run alone.
// held_open:0 is the walk run_digest did before session 13, kept here as its peer:
// every attribute, shape and value read by its path (a look-up of the path and an
// open by name per call); held_open:1 is run_digest now (Hdf5File::Object: each
// object opened once, through its open parent). Both must give the same digest
// (checked: the benchmark fails otherwise).
//
// Single thread; Time is wall time.

#include <benchmark/benchmark.h>

#include <oneapi/tbb/task_arena.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "engine/hdf5/hdf5_file.hpp"
#include "engine/job/job_file.hpp"
#include "engine/run/job_runner.hpp"
#include "engine/store/run_digest.hpp"
#include "engine/store/run_store.hpp"
#include "engine/tasks/task_list.hpp"

namespace ggk::bench {
namespace {

struct StagedRun {
  engine::JobSpec job;
  engine::RunRecord record;
};

const StagedRun& khepera_run() {
  static const std::unique_ptr<StagedRun> run = [] {
    engine::JobLoadOptions options;
    options.check_output = false;
    options.overrides = {"runs=1", "sweep.basis=[\"ggk\", \"ogk\"]"};
    auto staged = std::make_unique<StagedRun>();
    staged->job =
        engine::load_job_file(std::filesystem::path(GGK_SOURCE_DIR) / "jobs" / "khepera-paper.toml",
                              engine::task_tables(), options);
    tbb::task_arena arena(1);
    staged->record = arena.execute([&] { return engine::compute_run(staged->job, 0); });
    return staged;
  }();
  return *run;
}

void BM_StageRun(benchmark::State& state) {
  const StagedRun& run = khepera_run();
  std::int64_t datasets = 0;
  for (auto _ : state) {
    engine::Hdf5File file = engine::Hdf5File::create_in_memory("bench");
    const std::string staged = engine::stage_run(file, run.job, run.record);
    benchmark::DoNotOptimize(staged.data());
    state.PauseTiming();
    datasets = 0;
    std::vector<std::string> pending = {staged};
    while (!pending.empty()) {
      const std::string path = pending.back();
      pending.pop_back();
      if (file.object_kind(path) == engine::Hdf5File::ObjectKind::kDataset) {
        ++datasets;
        continue;
      }
      for (const std::string& member : file.member_names(path))
        pending.push_back(path + "/" + member);
    }
    state.ResumeTiming();
  }
  state.counters["datasets"] = static_cast<double>(datasets);
}
BENCHMARK(BM_StageRun)->Unit(benchmark::kMillisecond)->UseRealTime();

// ---------------------------------------------------------------- the peer walk

// FNV-1a, 64 bits, as engine/store/run_digest.cpp.
class Fnv1a {
 public:
  void add(const void* data, std::size_t size) {
    const auto* bytes = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < size; ++i) {
      hash_ ^= bytes[i];
      hash_ *= 0x100000001b3ULL;
    }
  }
  void add(const std::string& text) {
    add(text.data(), text.size());
    add("\0", 1);
  }
  void add(std::int64_t value) { add(&value, sizeof value); }
  std::uint64_t value() const { return hash_; }

 private:
  std::uint64_t hash_ = 0xcbf29ce484222325ULL;
};

bool left_out(const std::string& relative, const std::string& name) {
  if (name == "fit_seconds") return true;
  return relative.empty() && (name == "complete" || name == engine::kRunDigestAttribute ||
                              name == engine::kMetadataDigestAttribute);
}

// run_digest's walk before session 13, every call by path.
void add_by_path(const engine::Hdf5File& file, const std::string& path, const std::string& relative,
                 Fnv1a& hash) {
  if (!file.hard_link_address(path)) throw std::runtime_error(path + ": not a hard link");
  hash.add(relative);
  for (const std::string& name : file.attribute_names(path)) {
    if (left_out(relative, name)) continue;
    const engine::Hdf5File::Values values = file.read_attribute_values(path, name);
    hash.add(name);
    hash.add(values.type);
    for (const std::int64_t extent : values.shape) hash.add(extent);
    hash.add(static_cast<std::int64_t>(values.bytes.size()));
    hash.add(values.bytes.data(), values.bytes.size());
    for (const std::string& text : values.strings) hash.add(text);
  }
  switch (file.object_kind(path)) {
    case engine::Hdf5File::ObjectKind::kDataset: {
      hash.add("dataset");
      for (const std::int64_t extent : file.dataset_shape(path)) hash.add(extent);
      static const std::string kWallClock[] = {"fit_seconds"};
      const engine::Hdf5File::Values values = file.read_values(path, kWallClock);
      hash.add(values.type);
      hash.add(static_cast<std::int64_t>(values.bytes.size()));
      hash.add(values.bytes.data(), values.bytes.size());
      for (const std::string& text : values.strings) hash.add(text);
      return;
    }
    case engine::Hdf5File::ObjectKind::kGroup:
      hash.add("group");
      for (const std::string& member : file.member_names(path)) {
        add_by_path(file, path + "/" + member, relative + "/" + member, hash);
      }
      return;
    case engine::Hdf5File::ObjectKind::kOther:
      hash.add("other");
      return;
  }
}

void BM_RunDigest(benchmark::State& state) {
  const bool held_open = state.range(0) != 0;
  const StagedRun& run = khepera_run();
  engine::Hdf5File file = engine::Hdf5File::create_in_memory("bench");
  const std::string staged = engine::stage_run(file, run.job, run.record);
  const auto stored =
      static_cast<std::uint64_t>(file.read_int64_attribute(staged, engine::kRunDigestAttribute));
  for (auto _ : state) {
    std::uint64_t digest = 0;
    if (held_open) {
      digest = engine::run_digest(file, staged);
    } else {
      Fnv1a hash;
      add_by_path(file, staged, "", hash);
      digest = hash.value();
    }
    if (digest != stored) {
      state.SkipWithError("the walk's digest differs from the one stage_run stored");
      break;
    }
    benchmark::DoNotOptimize(digest);
  }
  state.SetLabel(held_open ? "held_open" : "by_path");
}
BENCHMARK(BM_RunDigest)
    ->ArgName("held_open")
    ->Arg(0)
    ->Arg(1)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace
}  // namespace ggk::bench

BENCHMARK_MAIN();
