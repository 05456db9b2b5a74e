// ggk merge (engine/store/results_merge.hpp): shards of a job (run_job with
// --runs A:B) join into the file the whole job writes; overlapping and foreign
// shards are refused, gaps named, and a refused merge writes nothing.

#include "engine/store/results_merge.hpp"

#include <cstdint>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "engine/hdf5/hdf5_file.hpp"
#include "engine/job/usage_error.hpp"
#include "engine/run/job_runner.hpp"
#include "engine/store/results_diff.hpp"
#include "engine/store/run_store.hpp"
#include "support/chunk_damage.hpp"
#include "support/determinism_job.hpp"
#include "support/ggk_binary.hpp"
#include "support/results_compare.hpp"

namespace ggk::engine {
namespace {

namespace fs = std::filesystem;
using namespace test_support;

class ResultsMergeTest : public JobRunnerTest {
 protected:
  // The determinism job with 4 runs (so that a gap can be a range).
  JobSpec four_runs(const std::string& name = "job.toml") const {
    std::string text = determinism_job(dir_ / "whole.h5");
    text.replace(text.find("runs = 3"), 8, "runs = 4");
    return load_job(name, text);
  }

  // Runs [first, last) of `job` into <dir>/<name>.
  fs::path shard(const JobSpec& job, const std::string& name, std::int32_t first,
                 std::int32_t last) const {
    RunOptions options = options_for(dir_ / name);
    options.runs = RunRange{first, last};
    run_job(job, options);
    return dir_ / name;
  }

  // merge_results' UsageError message (a failure when it merges).
  std::string refusal(const fs::path& output, const std::vector<fs::path>& shards,
                      const MergeOptions& options = {}) const {
    std::ostringstream log;
    try {
      merge_results(output, shards, options, log);
    } catch (const UsageError& error) {
      return error.what();
    }
    ADD_FAILURE() << "the merge into " << output << " was not refused: " << log.str();
    return {};
  }
};

TEST_F(ResultsMergeTest, ShardsMergeIntoTheFileTheWholeJobWrites) {
  const JobSpec job = four_runs();
  run_job(job, options_for(dir_ / "whole.h5"));
  // Out of order, and of uneven sizes: the merge follows the runs, not the list.
  const std::vector<fs::path> shards = {shard(job, "c.h5", 3, 4), shard(job, "a.h5", 0, 1),
                                        shard(job, "b.h5", 1, 3)};
  std::ostringstream log;
  merge_results(dir_ / "merged.h5", shards, {}, log);
  EXPECT_TRUE(contains(log.str(), "merged 4 of 4 runs from 3 shards"));

  std::ostringstream diff;
  EXPECT_TRUE(diff_results(dir_ / "whole.h5", dir_ / "merged.h5", diff)) << diff.str();
  expect_identical_results(job, dir_ / "whole.h5", dir_ / "merged.h5");
  EXPECT_EQ(summary_keys(dir_ / "merged.h5", "maze"), every_fit_once(job));
  const Hdf5File merged = Hdf5File::open_read_only(dir_ / "merged.h5");
  EXPECT_EQ(merged.read_int64_attribute("/", "runs"), 4);
  EXPECT_FALSE(merged.has_attribute("/", "runs_selected")) << "the merged file is the whole job's";
  // No temporary file left beside it.
  for (const auto& entry : fs::directory_iterator(dir_)) {
    EXPECT_EQ(entry.path().string().find(".merging-"), std::string::npos) << entry.path();
  }
}

TEST_F(ResultsMergeTest, OverlappingShardsAreRefusedNamingTheRunAndBothFiles) {
  const JobSpec job = four_runs();
  const fs::path a = shard(job, "a.h5", 0, 2), b = shard(job, "b.h5", 1, 4);
  const std::string message = refusal(dir_ / "merged.h5", {a, b});
  EXPECT_TRUE(contains(message, "run 1 is complete in both " + a.string() + " and " + b.string()));
  EXPECT_TRUE(contains(message, "overlapping"));
  EXPECT_FALSE(fs::exists(dir_ / "merged.h5"));
}

TEST_F(ResultsMergeTest, GapsAreNamedAndMergeOnlyWithAllowPartial) {
  const JobSpec job = four_runs();
  const fs::path a = shard(job, "a.h5", 0, 1), d = shard(job, "d.h5", 3, 4);
  const std::string message = refusal(dir_ / "merged.h5", {a, d});
  EXPECT_TRUE(contains(message, "2 of 4 runs are complete in no shard: 1-2"));
  EXPECT_TRUE(contains(message, "--allow-partial"));
  EXPECT_FALSE(fs::exists(dir_ / "merged.h5"));

  // With --allow-partial: the runs there are, and --resume computes the rest
  // into the file the whole job writes.
  std::ostringstream log;
  merge_results(dir_ / "merged.h5", std::vector<fs::path>{a, d}, {.allow_partial = true}, log);
  EXPECT_TRUE(contains(log.str(), "runs missing: 1-2"));
  {
    const Hdf5File merged = Hdf5File::open_read_only(dir_ / "merged.h5");
    EXPECT_TRUE(run_is_complete(merged, "maze", 0));
    EXPECT_FALSE(run_is_complete(merged, "maze", 1));
    EXPECT_FALSE(run_is_complete(merged, "maze", 2));
    EXPECT_TRUE(run_is_complete(merged, "maze", 3));
  }
  RunOptions resume = options_for(dir_ / "merged.h5");
  resume.resume = true;
  EXPECT_EQ(run_job(job, resume).runs_computed, 2);
  run_job(job, options_for(dir_ / "whole.h5"));
  expect_identical_results(job, dir_ / "whole.h5", dir_ / "merged.h5");
}

// Nothing copied is trusted unchecked: a shard with one flipped byte in a
// chunk, or a run cut short (its fits deleted), is refused naming the shard and
// the object, and the output is not made (before, the flipped byte was merged
// with exit 0, and a damaged fit_metrics crashed HDF5's copy).
TEST_F(ResultsMergeTest, ADamagedShardIsRefusedNamingItAndTheObject) {
  const JobSpec job = four_runs();
  const fs::path a = shard(job, "a.h5", 0, 2), b = shard(job, "b.h5", 2, 4);
  const std::string weights = "/maze/run_003/fits/ggk/k_0008_sigma3_brm_lambda1e-06/weights";
  fs::copy_file(b, dir_ / "flipped.h5");
  const ChunkPlace chunk = first_chunk(dir_ / "flipped.h5", weights);
  ASSERT_NE(chunk.address, HADDR_UNDEF) << weights;
  flip_byte(dir_ / "flipped.h5", chunk.address + chunk.size / 2);
  std::string message = refusal(dir_ / "out.h5", {a, dir_ / "flipped.h5"});
  EXPECT_TRUE(contains(message, (dir_ / "flipped.h5").string() + ": run 3 is damaged")) << message;
  EXPECT_TRUE(contains(message, weights)) << message;
  EXPECT_FALSE(fs::exists(dir_ / "out.h5"));

  fs::copy_file(b, dir_ / "cut.h5");
  {
    Hdf5File cut = Hdf5File::open_read_write(dir_ / "cut.h5");
    cut.remove("/maze/run_002/fits");
    cut.flush();
  }
  message = refusal(dir_ / "out.h5", {a, dir_ / "cut.h5"});
  EXPECT_TRUE(contains(message, "run 2 is damaged")) << message;
  EXPECT_TRUE(contains(message, "/maze/run_002/fits")) << message;
  EXPECT_FALSE(fs::exists(dir_ / "out.h5"));
  for (const auto& entry : fs::directory_iterator(dir_)) {
    EXPECT_FALSE(contains(entry.path().filename().string(), "merging")) << entry.path();
  }
}

TEST_F(ResultsMergeTest, AShardOfAnotherJobIsRefused) {
  const JobSpec job = four_runs();
  std::string other_text = determinism_job(dir_ / "whole.h5");
  other_text.replace(other_text.find("runs = 3"), 8, "runs = 4");
  other_text.replace(other_text.find("seed = 20240917"), 15, "seed = 20240918");
  const JobSpec other = load_job("other.toml", other_text);
  const fs::path a = shard(job, "a.h5", 0, 2), b = shard(other, "b.h5", 2, 4);
  const std::string message = refusal(dir_ / "merged.h5", {a, b});
  EXPECT_TRUE(contains(message, b.string() + " holds another job than " + a.string()));
  EXPECT_TRUE(contains(message, "seed"));
  EXPECT_FALSE(fs::exists(dir_ / "merged.h5"));
}

TEST_F(ResultsMergeTest, AnExistingOutputIsRefusedAndKept) {
  const JobSpec job = four_runs();
  const std::vector<fs::path> shards = {shard(job, "a.h5", 0, 4)};
  write_file(dir_ / "merged.h5", "older results");
  EXPECT_TRUE(contains(refusal(dir_ / "merged.h5", shards), "exists"));
  EXPECT_EQ(file_bytes(dir_ / "merged.h5"), "older results");
}

}  // namespace
}  // namespace ggk::engine
