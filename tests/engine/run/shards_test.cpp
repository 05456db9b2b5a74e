#include "engine/run/shards.hpp"

#include <sched.h>
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "engine/job/usage_error.hpp"

namespace ggk::engine {
namespace {

namespace fs = std::filesystem;

// An environment of the given variables only.
EnvironmentLookup environment_of(std::map<std::string, std::string> variables) {
  return [variables = std::move(variables)](const char* name) -> const char* {
    const auto found = variables.find(name);
    return found == variables.end() ? nullptr : found->second.c_str();
  };
}

const EnvironmentLookup kNoEnvironment = environment_of({});

// The message of the UsageError that `call` throws ("" when it throws none).
template <typename Call>
std::string usage_error_of(Call call) {
  try {
    call();
  } catch (const UsageError& e) {
    return e.what();
  }
  return "";
}

TEST(Shards, parse_index_and_count) {
  const Shard shard = parse_shard("2/5", kNoEnvironment);
  EXPECT_EQ(shard.index, 2);
  EXPECT_EQ(shard.count, 5);
  EXPECT_EQ(parse_shard("0/1", kNoEnvironment).count, 1);
}

TEST(Shards, parse_refuses_what_is_not_a_shard) {
  for (const char* text : {"", "3", "1/", "/4", "a/4", "1/4x", "-1/4", "1/-4", "1.0/4", " 1/4"}) {
    EXPECT_NE(usage_error_of([&] { parse_shard(text, kNoEnvironment); }).find("expected I/N"),
              std::string::npos)
        << text;
  }
  EXPECT_NE(usage_error_of([] {
              parse_shard("4/4", kNoEnvironment);
            }).find("shard 4 of 4 does not exist (shards are numbered 0..3)"),
            std::string::npos);
  EXPECT_NE(usage_error_of([] { parse_shard("0/0", kNoEnvironment); }).find("does not exist"),
            std::string::npos);
}

// Every split of every run count up to 40: contiguous, in order, covering each
// run once, sizes within one of each other.
TEST(Shards, runs_are_contiguous_balanced_and_cover_the_job) {
  for (std::int32_t runs = 1; runs <= 40; ++runs) {
    for (std::int32_t count = 1; count <= runs; ++count) {
      std::int32_t next = 0, smallest = runs, largest = 0;
      for (std::int32_t index = 0; index < count; ++index) {
        const RunRange range = shard_runs({index, count}, runs);
        ASSERT_EQ(range.first, next) << runs << " runs, shard " << index << "/" << count;
        ASSERT_GT(range.last, range.first);
        smallest = std::min(smallest, range.last - range.first);
        largest = std::max(largest, range.last - range.first);
        next = range.last;
      }
      EXPECT_EQ(next, runs);
      EXPECT_LE(largest - smallest, 1) << runs << " runs in " << count << " shards";
    }
  }
  // 20 runs in 4 (the README's array) and 30 in 4.
  EXPECT_EQ(shard_runs({1, 4}, 20).first, 5);
  EXPECT_EQ(shard_runs({1, 4}, 20).last, 10);
  EXPECT_EQ(shard_runs({0, 4}, 30).last, 7);
  EXPECT_EQ(shard_runs({3, 4}, 30).first, 22);
}

TEST(Shards, more_shards_than_runs_is_refused) {
  EXPECT_EQ(usage_error_of([] {
              shard_runs({0, 7}, 6);
            }),
            "--shard 0/7: the job has 6 runs, fewer than 7 shards (a shard would have no run): "
            "use at most 6 shards");
}

TEST(Shards, slurm_array_gives_index_and_count) {
  Shard shard = parse_shard("slurm", environment_of({{"SLURM_ARRAY_TASK_ID", "3"},
                                                     {"SLURM_ARRAY_TASK_COUNT", "4"},
                                                     {"SLURM_ARRAY_TASK_MIN", "0"},
                                                     {"SLURM_ARRAY_TASK_MAX", "3"},
                                                     {"SLURM_ARRAY_TASK_STEP", "1"}}));
  EXPECT_EQ(shard.index, 3);
  EXPECT_EQ(shard.count, 4);
  // MIN / MAX without COUNT (as older Slurm sets them)
  shard = parse_shard("slurm", environment_of({{"SLURM_ARRAY_TASK_ID", "0"},
                                               {"SLURM_ARRAY_TASK_MIN", "0"},
                                               {"SLURM_ARRAY_TASK_MAX", "1"}}));
  EXPECT_EQ(shard.index, 0);
  EXPECT_EQ(shard.count, 2);
}

TEST(Shards, slurm_refuses_outside_an_array_and_arrays_not_from_zero) {
  EXPECT_NE(usage_error_of([] {
              parse_shard("slurm", kNoEnvironment);
            }).find("SLURM_ARRAY_TASK_ID is not set: this is not a task of a Slurm job array"),
            std::string::npos);
  EXPECT_NE(usage_error_of([] {
              parse_shard("slurm", environment_of({{"SLURM_ARRAY_TASK_ID", "1"}}));
            }).find("the array's size is unknown"),
            std::string::npos);
  // sbatch --array=1-4
  EXPECT_NE(usage_error_of([] {
              parse_shard("slurm", environment_of({{"SLURM_ARRAY_TASK_ID", "1"},
                                                   {"SLURM_ARRAY_TASK_COUNT", "4"},
                                                   {"SLURM_ARRAY_TASK_MIN", "1"},
                                                   {"SLURM_ARRAY_TASK_MAX", "4"}}));
            }).find("the array starts at 1 (SLURM_ARRAY_TASK_MIN=1), not 0"),
            std::string::npos);
  // sbatch --array=0-6:2
  EXPECT_NE(usage_error_of([] {
              parse_shard("slurm", environment_of({{"SLURM_ARRAY_TASK_ID", "2"},
                                                   {"SLURM_ARRAY_TASK_COUNT", "4"},
                                                   {"SLURM_ARRAY_TASK_MIN", "0"},
                                                   {"SLURM_ARRAY_TASK_MAX", "6"},
                                                   {"SLURM_ARRAY_TASK_STEP", "2"}}));
            }).find("steps of 2"),
            std::string::npos);
  // sbatch --array=0,1,3
  EXPECT_NE(usage_error_of([] {
              parse_shard("slurm", environment_of({{"SLURM_ARRAY_TASK_ID", "3"},
                                                   {"SLURM_ARRAY_TASK_COUNT", "3"},
                                                   {"SLURM_ARRAY_TASK_MIN", "0"},
                                                   {"SLURM_ARRAY_TASK_MAX", "3"}}));
            }).find("a list with gaps"),
            std::string::npos);
  EXPECT_NE(usage_error_of([] {
              parse_shard("slurm", environment_of({{"SLURM_ARRAY_TASK_ID", "x"},
                                                   {"SLURM_ARRAY_TASK_COUNT", "3"}}));
            }).find("SLURM_ARRAY_TASK_ID=x is not a whole number"),
            std::string::npos);
}

TEST(Shards, output_names_sit_beside_the_output) {
  EXPECT_EQ(shard_output("results/x.h5", {1, 4}), fs::path("results/x.shard-1-of-4.h5"));
  EXPECT_EQ(shard_output("x.h5", {0, 2}), fs::path("x.shard-0-of-2.h5"));
  EXPECT_EQ(shard_output("/a/b.c/khepera-paper.h5", {11, 12}),
            fs::path("/a/b.c/khepera-paper.shard-11-of-12.h5"));
}

TEST(Shards, select_names_the_shard_after_o_or_the_job) {
  JobSpec job;
  job.runs = 10;
  job.output.file = "results/job.h5";
  RunOptions options;
  select_shard({2, 3}, job, options);
  ASSERT_TRUE(options.runs.has_value());
  EXPECT_EQ(options.runs->first, 6);
  EXPECT_EQ(options.runs->last, 10);
  EXPECT_EQ(options.output, fs::path("results/job.shard-2-of-3.h5"));
  RunOptions with_o;
  with_o.output = "elsewhere/mine.h5";
  select_shard({0, 3}, job, with_o);
  EXPECT_EQ(with_o.output, fs::path("elsewhere/mine.shard-0-of-3.h5"));
  EXPECT_EQ(with_o.runs->last, 3);
}

class ShardFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    folder_ = fs::temp_directory_path() / ("ggk-shards-test-" + std::to_string(::getpid()));
    fs::remove_all(folder_);
    fs::create_directories(folder_);
  }
  void TearDown() override { fs::remove_all(folder_); }
  void touch(const std::string& name) { std::ofstream(folder_ / name) << "x"; }
  fs::path folder_;
};

TEST_F(ShardFiles, finds_every_shard_in_order_and_nothing_else) {
  for (const char* name :
       {"x.shard-2-of-3.h5", "x.shard-0-of-3.h5", "x.shard-1-of-3.h5",
        // not shards of x.h5: temporaries, locks, other outputs, odd names
        "x.shard-1-of-3.h5.part", "x.shard-1-of-3.h5.lock", "x.h5", "y.shard-0-of-3.h5",
        "xx.shard-0-of-3.h5", "x.shard-01-of-3.h5", "x.shard-5-of-3.h5", "x.shard-a-of-3.h5"}) {
    touch(name);
  }
  const auto shards = find_shards(folder_ / "x.h5", false);
  ASSERT_EQ(shards.size(), 3U);
  for (std::int32_t i = 0; i < 3; ++i) {
    EXPECT_EQ(shards[i], folder_ / ("x.shard-" + std::to_string(i) + "-of-3.h5"));
  }
}

TEST_F(ShardFiles, a_missing_shard_is_named) {
  touch("x.shard-0-of-4.h5");
  touch("x.shard-2-of-4.h5");
  touch("x.shard-3-of-4.h5.part");  // still being written: not a shard yet
  touch("x.shard-01-of-4.h5");      // not a name ggk writes
  const std::string message = usage_error_of([&] { find_shards(folder_ / "x.h5", false); });
  EXPECT_NE(message.find("2 of 4 shards of " + (folder_ / "x.h5").string() +
                         " missing: " + (folder_ / "x.shard-1-of-4.h5").string() + ", " +
                         (folder_ / "x.shard-3-of-4.h5").string()),
            std::string::npos)
      << message;
  EXPECT_EQ(find_shards(folder_ / "x.h5", true).size(), 2U);  // --allow-partial
}

TEST_F(ShardFiles, none_or_two_splits_are_refused) {
  EXPECT_NE(usage_error_of([&] { find_shards(folder_ / "x.h5", false); })
                .find("no shards of " + (folder_ / "x.h5").string() + ": no file " +
                      (folder_ / "x.shard-I-of-N.h5").string()),
            std::string::npos);
  touch("x.shard-0-of-2.h5");
  touch("x.shard-1-of-2.h5");
  touch("x.shard-0-of-3.h5");
  EXPECT_NE(
      usage_error_of([&] { find_shards(folder_ / "x.h5", false); }).find("from 2 different splits"),
      std::string::npos);
}

}  // namespace
}  // namespace ggk::engine
