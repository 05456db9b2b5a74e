// The memory check of `ggk run` (engine/run/memory_check.hpp; issue 13, item 10):
// the job estimate and what it names, the memory available, and through the
// binary the three jobs of the issue, which validate but cannot run: each is
// refused with status 2 and a message naming the estimate before any output
// exists. The binary runs under `ulimit -v` (4 GiB) and a timeout, so a check
// that let such a job through fails fast instead of exhausting the machine.
// Under AddressSanitizer, whose shadow memory needs terabytes of address space,
// only the timeout applies.

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "engine/job/sweep.hpp"
#include "engine/run/memory_check.hpp"
#include "engine/tasks/task_list.hpp"
#include "support/ggk_binary.hpp"
#include "support/job_text.hpp"

namespace ggk::engine {
namespace {

namespace fs = std::filesystem;
using namespace test_support;

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

// A maze job: `runs` runs, [maze] series x steps_per_series, output <scratch>/out/big.h5.
std::string maze_job(const std::string& runs, const std::string& series, const std::string& steps) {
  return "name = \"big\"\ntask = \"maze\"\nruns = " + runs +
         "\nseed = 1\n[sweep]\nkernels = [4, 8]\nsigma = [2.0]\n[maze]\nseries = " + series +
         "\nsteps_per_series = " + steps + "\nmap = \"\"\"\n" + kMap +
         "\"\"\"\n[output]\nfile = \"%DIR%/out/big.h5\"\n";
}

// A Khepera job whose SOM has rows x cols units, on series x steps_per_series walks.
std::string khepera_job(const std::string& rows, const std::string& cols,
                        const std::string& steps) {
  return "name = \"big\"\ntask = \"khepera\"\nruns = 1\nseed = 1\n[sweep]\nkernels = [5]\n"
         "sigma = [1000.0]\n[khepera]\nseries = 1\nsteps_per_series = " +
         steps + "\n[khepera.som]\nrows = " + rows + "\ncols = " + cols +
         "\n[khepera.arena]\nmin = [0.0, 0.0]\nmax = [40.0, 40.0]\n"
         "start = { x = 20.0, y = 20.0, heading_deg = 0.0 }\n[output]\nfile = "
         "\"%DIR%/out/big.h5\"\n";
}

JobSpec parse(const std::string& text) {
  return parse_unchecked(substitute(text, "DIR", "."), "big.toml");
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

class MemoryCheckCli : public GgkBinaryTest {
 protected:
  void SetUp() override {
    GgkBinaryTest::SetUp();
    if (IsSkipped() || HasFatalFailure()) return;
    fs::create_directories(dir_ / "out");
  }

  fs::path write_job(const std::string& text) const {
    return test_support::write_job(dir_, "big.toml", text);
  }

  // ggk with `args` under a 4 GiB address-space limit and a 120 s timeout.
  Outcome ggk(const std::vector<std::string>& args) const {
    return GgkBinaryTest::ggk(
        args, {.address_space_kib = kAddressSanitizer ? 0 : 4194304, .timeout_seconds = 120});
  }
};

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
    // validate is a dry run: it refuses what run refuses, with run's message;
    // --ignore-memory-check accepts the well-formed job, as it lets run start it.
    const Outcome validated = ggk({"validate", job.string(), "-j", "2"});
    EXPECT_EQ(validated.status, kUserError) << validated.err;
    EXPECT_TRUE(contains(validated.err, "ggk: error: job 'big' needs about ")) << validated.err;
    EXPECT_TRUE(contains(validated.err, c.names));
    EXPECT_EQ(ggk({"validate", job.string(), "--ignore-memory-check"}).status, 0);
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

// "61.0 MB" at `at` in `text` -> 61e6 (format_bytes' units); NaN when absent.
double bytes_at(const std::string& text, std::size_t at) {
  if (at == std::string::npos) return std::nan("");
  std::size_t used = 0;
  const double value = std::stod(text.substr(at), &used);
  const std::string unit = text.substr(at + used + 1, 2);
  const double scale = unit == "kB" ? 1e3 : unit == "MB" ? 1e6 : unit == "GB" ? 1e9 : 1.0;
  return value * scale;
}

TEST_F(MemoryCheckCli, UnderAnAddressSpaceLimitNothingHangsAndWhatPassesRuns) {
  if (kAddressSanitizer) GTEST_SKIP() << "AddressSanitizer's shadow memory needs the address space";
  // OpenBLAS's thread pool retries its 128 MiB work buffer forever: under these
  // limits `validate` never exited and `run` spun after (or instead of) the check.
  const fs::path job = write_job(maze_job("2", "2", "50"));
  auto limited = [&](const std::vector<std::string>& args, std::int64_t mib) {
    return GgkBinaryTest::ggk(args, {.address_space_kib = mib * 1024, .timeout_seconds = 60});
  };
  // validate applies run's check (all cores' reservations by default): it
  // exits at once, refusing as run would; past the check it accepts the job.
  const Outcome validated = limited({"validate", job.string()}, 200);
  EXPECT_EQ(validated.status, kUserError) << validated.err;
  EXPECT_TRUE(contains(validated.err, "the address-space limit (ulimit -v) of ")) << validated.err;
  const Outcome forced = limited({"validate", job.string(), "--ignore-memory-check"}, 200);
  EXPECT_EQ(forced.status, 0) << forced.err;

  // Refused: the threads' reservations are named, nothing is written.
  const std::int64_t tight = 400;
  const Outcome refused = limited({"run", job.string(), "-q", "-j", "2"}, tight);
  ASSERT_EQ(refused.status, kUserError) << refused.err;
  EXPECT_TRUE(contains(refused.err, "the address-space limit (ulimit -v) of "));
  EXPECT_TRUE(contains(refused.err, " the threads reserve (BLAS buffers, malloc arenas, stacks)"));
  EXPECT_TRUE(contains(refused.err, "raise the address-space limit (ulimit -v)"));
  EXPECT_TRUE(fs::is_empty(dir_ / "out"));

  // The limit the check asks for (what is in use, what the threads reserve and
  // the job, plus a margin for what the process maps before the check) is
  // enough to run the job.
  const std::string& err = refused.err;
  const std::string needs = "needs about ", less = ", less ", and_ = " in use and ";
  const double needed = bytes_at(err, err.find(needs) + needs.size());
  const double in_use = bytes_at(err, err.find(less) + less.size());
  const double reserved = bytes_at(err, err.find(and_) + and_.size());
  ASSERT_TRUE(std::isfinite(needed) && std::isfinite(in_use) && std::isfinite(reserved)) << err;
  const auto enough = static_cast<std::int64_t>((needed + in_use + reserved) / 1048576.0) + 16;
  const Outcome ran = limited({"run", job.string(), "-q", "-j", "2"}, enough);
  EXPECT_EQ(ran.status, 0) << "at " << enough << " MiB: " << ran.err;
  EXPECT_TRUE(fs::exists(dir_ / "out" / "big.h5"));
}

}  // namespace
}  // namespace ggk::engine
