// The memory check of `ggk run` (engine/run/memory_check.hpp; issue 13, item 10):
// the job estimate and what it names, the memory available, and through the
// binary the three jobs of the issue, which validate but cannot run: each is
// refused with status 2 and a message naming the estimate before any output
// exists. The binary runs under `ulimit -v` (4 GiB) and a timeout, so a check
// that let such a job through fails fast instead of exhausting the machine.
// Under AddressSanitizer, whose shadow memory needs terabytes of address space,
// only the timeout applies.

#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "engine/job/job_file.hpp"
#include "engine/job/sweep.hpp"
#include "engine/run/memory_check.hpp"
#include "engine/tasks/task_list.hpp"

namespace ggk::engine {
namespace {

namespace fs = std::filesystem;

constexpr int kUserError = 2;

#if defined(__SANITIZE_ADDRESS__)
constexpr bool kAddressSanitizer = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
constexpr bool kAddressSanitizer = true;
#else
constexpr bool kAddressSanitizer = false;
#endif
#else
constexpr bool kAddressSanitizer = false;
#endif

constexpr const char* kMap =
    "#######\n"
    "#.....#\n"
    "#.###.#\n"
    "#....G#\n"
    "#######\n";

// A maze job: `runs` runs, [maze] series x steps_per_series, output %OUT%.
std::string maze_job(const std::string& runs, const std::string& series, const std::string& steps) {
  return "name = \"big\"\ntask = \"maze\"\nruns = " + runs +
         "\nseed = 1\n[sweep]\nkernels = [4, 8]\nsigma = [2.0]\n[maze]\nseries = " + series +
         "\nsteps_per_series = " + steps + "\nmap = \"\"\"\n" + kMap +
         "\"\"\"\n[output]\nfile = \"%OUT%\"\n";
}

// A Khepera job whose SOM has rows x cols units, on series x steps_per_series walks.
std::string khepera_job(const std::string& rows, const std::string& cols,
                        const std::string& steps) {
  return "name = \"big\"\ntask = \"khepera\"\nruns = 1\nseed = 1\n[sweep]\nkernels = [5]\n"
         "sigma = [1000.0]\n[khepera]\nseries = 1\nsteps_per_series = " +
         steps + "\n[khepera.som]\nrows = " + rows + "\ncols = " + cols +
         "\n[khepera.arena]\nmin = [0.0, 0.0]\nmax = [40.0, 40.0]\n"
         "start = { x = 20.0, y = 20.0, heading_deg = 0.0 }\n[output]\nfile = \"%OUT%\"\n";
}

std::string replaced(std::string text, const std::string& key, const std::string& value) {
  for (std::size_t at = text.find(key); at != std::string::npos; at = text.find(key, at)) {
    text.replace(at, key.size(), value);
    at += value.size();
  }
  return text;
}

JobSpec parse(const std::string& text) {
  JobLoadOptions options;
  options.check_output = false;
  return parse_job(replaced(text, "%OUT%", "out.h5"), "big.toml", task_tables(), options);
}

TEST(MemoryCheck, EveryTaskEstimatesItsRuns) {
  for (const TaskDefinition& task : registered_tasks()) {
    EXPECT_NE(task.estimate_run_bytes, nullptr) << task.table.name;
  }
}

TEST(MemoryCheck, RunsAtOnceFollowTheThreadsAndTheRuns) {
  const JobSpec job = parse(maze_job("8", "5", "1000"));
  const JobMemoryEstimate one = estimate_job_memory(job, 1, 8);
  const JobMemoryEstimate four = estimate_job_memory(job, 4, 8);
  EXPECT_GT(one.per_run, 0.0);
  EXPECT_EQ(one.per_run, four.per_run);
  EXPECT_GT(four.bytes, one.bytes + 2.0 * one.per_run);  // 4 runs at once, not 1
  // More threads than runs and fits: no more runs at once than there are runs,
  // no more fits than the run has sweep points.
  const auto points = static_cast<std::int32_t>(expand_sweep(job).size());
  EXPECT_EQ(estimate_job_memory(job, 64, 1).bytes, estimate_job_memory(job, points, 1).bytes);
  EXPECT_GT(estimate_job_memory(job, 2, 1).bytes, estimate_job_memory(job, 1, 1).bytes);
  EXPECT_GT(estimate_job_memory(job, 1, 1).bytes, 48e6);  // the program itself
}

TEST(MemoryCheck, TwoBillionRunsNeedTerabytesOfBookkeeping) {
  const JobSpec job = parse(maze_job("2147483647", "5", "100"));
  const JobMemoryEstimate e = estimate_job_memory(job, 2, job.runs);
  EXPECT_TRUE(std::isfinite(e.bytes));
  EXPECT_GT(e.bytes, 2147483647.0 * 2 * 1000.0);  // a summary row per fit
  EXPECT_NE(e.largest.find("the summary table"), std::string::npos) << e.largest;
  EXPECT_NE(e.largest.find("2147483647 runs"), std::string::npos) << e.largest;
  // A shard of it is small.
  EXPECT_LT(estimate_job_memory(job, 2, 10).bytes, 200e6);
}

TEST(MemoryCheck, NamesTheSomThatDominates) {
  const JobSpec job = parse(khepera_job("40000", "40000", "1600000000"));
  const JobMemoryEstimate e = estimate_job_memory(job, 2, 1);
  EXPECT_GT(e.per_run, 10e9);
  EXPECT_NE(e.largest.find("a 40000 x 40000 SOM"), std::string::npos) << e.largest;
}

TEST(MemoryCheck, AvailableMemoryIsKnownOnLinux) {
  const AvailableMemory available = available_memory();
  EXPECT_TRUE(std::isfinite(available.bytes));
  EXPECT_GT(available.bytes, 0.0);
  EXPECT_FALSE(available.source.empty());
}

// ------------------------------------------------------------- the binary

struct Outcome {
  int status = -1;
  std::string err;
};

class MemoryCheckCli : public ::testing::Test {
 protected:
  void SetUp() override {
    const char* binary_dir = std::getenv("GGK_BINARY_DIR");
    if (binary_dir == nullptr) GTEST_SKIP() << "GGK_BINARY_DIR is not set (run through ctest)";
    binary_ = fs::path(binary_dir) / "ggk";
    ASSERT_TRUE(fs::exists(binary_)) << binary_ << " is missing: build the ggk target";
    std::string pattern = (fs::temp_directory_path() / "ggk-memory-XXXXXX").string();
    ASSERT_NE(::mkdtemp(pattern.data()), nullptr);
    dir_ = pattern;
    fs::create_directories(dir_ / "out");
  }
  void TearDown() override {
    std::error_code ignored;
    if (!dir_.empty()) fs::remove_all(dir_, ignored);
  }

  fs::path write_job(const std::string& text) const {
    const fs::path path = dir_ / "big.toml";
    std::ofstream(path) << replaced(text, "%OUT%", (dir_ / "out" / "big.h5").string());
    return path;
  }

  // ggk with `args` under a 4 GiB address-space limit and a 120 s timeout.
  Outcome ggk(const std::vector<std::string>& args) const {
    std::string command = kAddressSanitizer ? "" : "ulimit -v 4194304; ";
    command += "exec timeout 120 '" + binary_.string() + "'";
    for (const std::string& arg : args) command += " '" + arg + "'";
    const fs::path err = dir_ / "stderr.txt";
    command += " </dev/null >/dev/null 2>'" + err.string() + "'";
    const int raw = std::system(("bash -c \"" + command + "\"").c_str());
    Outcome outcome;
    if (raw != -1 && WIFEXITED(raw)) outcome.status = WEXITSTATUS(raw);
    std::ifstream in(err);
    outcome.err.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    return outcome;
  }

  fs::path binary_;
  fs::path dir_;
};

::testing::AssertionResult contains(const std::string& text, const std::string& part) {
  if (text.find(part) != std::string::npos) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "\"" << text << "\" does not contain \"" << part << "\"";
}

TEST_F(MemoryCheckCli, JobsThatCannotFitAreRefusedBeforeAnyOutputExists) {
  struct Case {
    std::string what, job, names;
  };
  const std::vector<Case> cases = {
      {"steps_per_series = 2147483647", maze_job("1", "1", "2147483647"), "2147483647 samples"},
      {"a 40000 x 40000 SOM", khepera_job("40000", "40000", "1600000000"), "SOM"},
      {"runs = 2147483647", maze_job("2147483647", "5", "100"), "the summary table"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.what);
    const fs::path job = write_job(c.job);
    for (const std::vector<std::string>& extra :
         {std::vector<std::string>{}, std::vector<std::string>{"--overwrite"},
          std::vector<std::string>{"--resume"}}) {
      std::vector<std::string> args = {"run", job.string(), "-q", "-j", "2"};
      args.insert(args.end(), extra.begin(), extra.end());
      const Outcome outcome = ggk(args);
      EXPECT_EQ(outcome.status, kUserError) << outcome.err;
      EXPECT_TRUE(contains(outcome.err, "ggk: error: job 'big' needs about "));
      EXPECT_TRUE(contains(outcome.err, " of memory, more than the "));
      EXPECT_TRUE(contains(outcome.err, " available ("));
      EXPECT_TRUE(contains(outcome.err, c.names));
      EXPECT_TRUE(contains(outcome.err, "--ignore-memory-check"));
      EXPECT_TRUE(fs::is_empty(dir_ / "out")) << "an output file was created";
    }
    // validate accepts the job: it is well-formed, only too big for this machine.
    EXPECT_EQ(ggk({"validate", job.string()}).status, 0);
  }
}

TEST_F(MemoryCheckCli, ARefusedOverwriteLeavesTheOldResults) {
  const fs::path output = dir_ / "out" / "big.h5";
  std::ofstream(output) << "old results";
  const fs::path job = write_job(maze_job("1", "1", "2147483647"));
  const Outcome outcome = ggk({"run", job.string(), "-q", "--overwrite"});
  EXPECT_EQ(outcome.status, kUserError) << outcome.err;
  std::ifstream in(output);
  EXPECT_EQ(std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()),
            "old results");
  EXPECT_EQ(std::distance(fs::directory_iterator(dir_ / "out"), fs::directory_iterator()), 1);
}

TEST_F(MemoryCheckCli, IgnoreMemoryCheckLetsTheJobPastTheCheck) {
  // The job would not fit; with the flag the check only notes it, and the run
  // goes on to fail at the next step (its output folder is missing) without
  // computing anything.
  const fs::path job = write_job(maze_job("1", "1", "2147483647"));
  const std::string missing = (dir_ / "missing" / "x.h5").string();
  const Outcome outcome = ggk({"run", job.string(), "-q", "-o", missing, "--ignore-memory-check"});
  EXPECT_EQ(outcome.status, kUserError) << outcome.err;
  EXPECT_TRUE(contains(outcome.err, "running it anyway (--ignore-memory-check)"));
  EXPECT_TRUE(contains(outcome.err, "does not exist"));
  // A job that fits runs with or without the flag.
  const fs::path small = write_job(maze_job("1", "2", "50"));
  EXPECT_EQ(ggk({"run", small.string(), "-q", "-j", "1"}).status, 0);
  EXPECT_EQ(
      ggk({"run", small.string(), "-q", "-j", "1", "--overwrite", "--ignore-memory-check"}).status,
      0);
  EXPECT_TRUE(fs::exists(dir_ / "out" / "big.h5"));
}

}  // namespace
}  // namespace ggk::engine
