#include "engine/run/job_runner.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include <gtest/gtest.h>

#include "engine/hdf5/hdf5_file.hpp"
#include "engine/job/job_file.hpp"
#include "engine/job/sweep.hpp"
#include "engine/run/progress.hpp"
#include "engine/store/results_info.hpp"
#include "engine/store/run_store.hpp"
#include "engine/tasks/discrete_protocol.hpp"
#include "engine/tasks/task_list.hpp"
#include "sims/maze/maze.hpp"
#include "sims/maze/maze_config.hpp"

namespace ggk::engine {
namespace {

namespace fs = std::filesystem;

// Two small rooms and a corridor: 27 states, one of them the goal.
constexpr const char* kSmallMap = R"(
#########
#...#...#
#.#.....#
#...#..G#
##.####.#
#.......#
#########
)";

// The determinism job: 3 runs x (2 bases x 2 kernel counts x 2 solvers); slip
// makes the samples and the policy tests draw random numbers.
std::string determinism_job(const fs::path& output) {
  return std::string(R"(name = "determinism"
task = "maze"
runs = 3
seed = 20240917
[sweep]
basis = ["ggk", "ogk"]
kernels = [4, 8]
sigma = [3.0]
solver = ["brm", "lstdq"]
[maze]
map = """)") +
         kSmallMap + R"("""
slip = 0.2
series = 6
steps_per_series = 80
test_max_steps = 40
[output]
file = ")" +
         output.string() +
         R"("
)";
}

// A scratch folder per test, removed afterwards.
class JobRunnerTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string pattern = (fs::temp_directory_path() / "ggk-job-runner-XXXXXX").string();
    ASSERT_NE(::mkdtemp(pattern.data()), nullptr);
    dir_ = pattern;
  }
  void TearDown() override {
    std::error_code ignored;
    fs::remove_all(dir_, ignored);
  }

  // Writes `text` to <dir>/<name> and loads it as a job.
  JobSpec load_job(const std::string& name, const std::string& text) const {
    const fs::path path = dir_ / name;
    std::ofstream(path, std::ios::binary) << text;
    return load_job_file(path, task_tables());
  }

  fs::path dir_;
};

RunOptions options_for(const fs::path& output, std::int32_t threads = 2) {
  RunOptions options;
  options.output = output;
  options.threads = threads;
  options.quiet = true;
  return options;
}

std::string file_bytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// ---------------------------------------------------------------------------
// Bit-exact comparison of two results files.

template <class T>
bool same_bits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() &&
         (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

// Same variant alternative and same value; doubles by their bits (NaN == NaN).
bool same_cell(const TableValue& a, const TableValue& b) {
  if (a.index() != b.index()) return false;
  if (const auto* x = std::get_if<double>(&a)) {
    return std::bit_cast<std::uint64_t>(*x) == std::bit_cast<std::uint64_t>(std::get<double>(b));
  }
  return a == b;
}

std::string cell_text(const TableValue& v) {
  return std::visit(
      [](const auto& x) -> std::string {
        using T = std::decay_t<decltype(x)>;
        if constexpr (std::is_same_v<T, std::string>) {
          return "\"" + x + "\"";
        } else {
          return std::to_string(x);
        }
      },
      v);
}

// Tables equal cell by cell, except the columns named in `skip`.
void expect_same_table(const Hdf5File& a, const Hdf5File& b, const std::string& path,
                       const std::set<std::string>& skip = {"fit_seconds"}) {
  SCOPED_TRACE(path);
  const std::vector<TableColumn> columns = a.read_table_columns(path);
  ASSERT_EQ(columns, b.read_table_columns(path));
  const std::vector<TableRow> rows_a = a.read_table(path);
  const std::vector<TableRow> rows_b = b.read_table(path);
  ASSERT_EQ(rows_a.size(), rows_b.size());
  for (std::size_t r = 0; r < rows_a.size(); ++r) {
    for (std::size_t c = 0; c < columns.size(); ++c) {
      if (skip.contains(columns[c].name)) continue;
      EXPECT_TRUE(same_cell(rows_a[r][c], rows_b[r][c]))
          << "row " << r << ", column " << columns[c].name << ": " << cell_text(rows_a[r][c])
          << " vs " << cell_text(rows_b[r][c]);
    }
  }
}

template <class T>
void expect_same_vector(const Hdf5File& a, const Hdf5File& b, const std::string& path) {
  ASSERT_EQ(a.exists(path), b.exists(path)) << path;
  if (!a.exists(path)) return;
  EXPECT_TRUE(same_bits(a.read_vector<T>(path), b.read_vector<T>(path))) << path;
}

void expect_same_matrix(const Hdf5File& a, const Hdf5File& b, const std::string& path) {
  const RowMajorArray<double> x = a.read_matrix<double>(path);
  const RowMajorArray<double> y = b.read_matrix<double>(path);
  EXPECT_EQ(x.rows, y.rows) << path;
  EXPECT_EQ(x.cols, y.cols) << path;
  EXPECT_TRUE(same_bits(x.data, y.data)) << path;
}

// Every deterministic number of every run: fit_metrics (bar fit_seconds), each
// fit's arrays and status, the samples and the graph; and the summary.
void expect_identical_results(const JobSpec& job, const fs::path& path_a, const fs::path& path_b) {
  const Hdf5File a = Hdf5File::open_read_only(path_a);
  const Hdf5File b = Hdf5File::open_read_only(path_b);
  const std::vector<SweepPoint> points = expand_sweep(job);
  for (std::int32_t run = 0; run < job.runs; ++run) {
    const std::string group = run_group(job.task, run);
    SCOPED_TRACE(group);
    ASSERT_TRUE(run_is_complete(a, job.task, run));
    ASSERT_TRUE(run_is_complete(b, job.task, run));
    expect_same_table(a, b, group + "/fit_metrics");
    for (const SweepPoint& point : points) {
      const std::string fit = group + "/fits/" + fit_group_name(job, point);
      SCOPED_TRACE(fit);
      EXPECT_EQ(a.read_string_attribute(fit, "status"), b.read_string_attribute(fit, "status"));
      expect_same_vector<std::int32_t>(a, b, fit + "/centers");
      expect_same_vector<double>(a, b, fit + "/weights");
      expect_same_vector<std::int32_t>(a, b, fit + "/policy");
      expect_same_vector<std::int32_t>(a, b, fit + "/steps_to_goal");
      expect_same_vector<double>(a, b, fit + "/state_values");
      expect_same_vector<std::int32_t>(a, b, fit + "/history/policy_changes");
      expect_same_vector<double>(a, b, fit + "/history/relative_residual");
      expect_same_vector<double>(a, b, fit + "/history/rcond");
    }
    const std::string samples = group + "/samples";
    expect_same_matrix(a, b, samples + "/observations");
    expect_same_vector<std::int32_t>(a, b, samples + "/actions");
    expect_same_vector<double>(a, b, samples + "/rewards");
    expect_same_matrix(a, b, samples + "/next_observations");
    expect_same_vector<std::uint8_t>(a, b, samples + "/terminals");
    const std::string graph = group + "/graph";
    expect_same_vector<std::int64_t>(a, b, graph + "/indptr");
    expect_same_vector<std::int32_t>(a, b, graph + "/indices");
    expect_same_vector<double>(a, b, graph + "/weights");
    expect_same_matrix(a, b, graph + "/nodes");
  }
  expect_same_table(a, b, "/" + job.task + "/summary");
}

// (run, sweep_point) of every summary row, in order.
std::vector<std::pair<std::int32_t, std::int32_t>> summary_keys(const fs::path& path,
                                                                const std::string& task) {
  const Hdf5File file = Hdf5File::open_read_only(path);
  std::vector<std::pair<std::int32_t, std::int32_t>> keys;
  for (const TableRow& row : file.read_table("/" + task + "/summary")) {
    keys.emplace_back(std::get<std::int32_t>(row.at(0)), std::get<std::int32_t>(row.at(1)));
  }
  return keys;
}

std::vector<std::pair<std::int32_t, std::int32_t>> every_fit_once(const JobSpec& job) {
  std::vector<std::pair<std::int32_t, std::int32_t>> keys;
  const auto points = static_cast<std::int32_t>(expand_sweep(job).size());
  for (std::int32_t run = 0; run < job.runs; ++run) {
    for (std::int32_t p = 0; p < points; ++p) keys.emplace_back(run, p);
  }
  return keys;
}

// "2024-09-17T08:30:00Z" (std::regex would do, but GCC 12 warns inside it
// under the sanitizers).
bool is_utc_timestamp(const std::string& text) {
  const std::string pattern = "dddd-dd-ddTdd:dd:ddZ";
  if (text.size() != pattern.size()) return false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const bool digit = text[i] >= '0' && text[i] <= '9';
    if (pattern[i] == 'd' ? !digit : text[i] != pattern[i]) return false;
  }
  return true;
}

// ---------------------------------------------------------------------------

TEST(Progress, EtaIsUnknownUntilTheFirstRunEnds) {
  EXPECT_EQ(eta_text(0, 10, 30.0), "--");
  EXPECT_EQ(eta_text(1, 10, 30.0), "270s");
  EXPECT_EQ(eta_text(10, 10, 30.0), "0s");
}

TEST(ConfidenceIntervals, StudentTMatchesScipy) {
  // scipy.stats.t.ppf(0.975, dof)
  EXPECT_NEAR(student_t_975(1), 12.706205, 1e-6);
  EXPECT_NEAR(student_t_975(29), 2.045230, 1e-6);
  EXPECT_NEAR(student_t_975(31), 2.0395134463964077, 1e-5);
  EXPECT_NEAR(student_t_975(40), 2.0210753829953374, 1e-5);
  EXPECT_NEAR(student_t_975(100), 1.9839715184496334, 1e-6);
  EXPECT_NEAR(student_t_975(1000), 1.9623390808264074, 1e-6);
  const std::vector<double> values = {1.0, 2.0, 3.0, 4.0, std::nan("")};
  const Interval ci = mean_interval(values);
  EXPECT_DOUBLE_EQ(ci.estimate, 2.5);
  // sd = 1.2910, n = 4: half-width t(3) sd / 2 = 2.054
  EXPECT_NEAR(ci.high - ci.estimate, 3.182446 * std::sqrt(5.0 / 3.0) / 2.0, 1e-5);
}

TEST(ConfidenceIntervals, WilsonStaysInsideZeroOneAndIsWideAtTheEnds) {
  const Interval none = wilson_interval(0, 30);
  EXPECT_EQ(none.estimate, 0.0);
  EXPECT_EQ(none.low, 0.0);
  EXPECT_NEAR(none.high, 0.11351, 1e-4);  // statsmodels proportion_confint(0, 30, method="wilson")
  const Interval all = wilson_interval(30, 30);
  EXPECT_NEAR(all.low, 1.0 - 0.11351, 1e-4);
  EXPECT_EQ(all.high, 1.0);
  const Interval some = wilson_interval(20, 30);
  EXPECT_NEAR(some.low, 0.48779, 1e-4);
  EXPECT_NEAR(some.high, 0.80774, 1e-4);
}

TEST_F(JobRunnerTest, ResultsAreBitIdenticalForOneTwoAndEightThreads) {
  const JobSpec job = load_job("job.toml", determinism_job(dir_ / "unused.h5"));
  const std::vector<std::int32_t> thread_counts = {1, 2, 8};
  for (std::int32_t threads : thread_counts) {
    const fs::path output = dir_ / ("threads_" + std::to_string(threads) + ".h5");
    const RunSummary summary = run_job(job, options_for(output, threads));
    EXPECT_EQ(summary.runs_computed, 3);
    EXPECT_EQ(summary.fits, 3 * 8);
    EXPECT_EQ(summary.failed_fits, 0);
  }
  // The comparison must see real fits: converged policies, goals reached.
  {
    const Hdf5File file = Hdf5File::open_read_only(dir_ / "threads_1.h5");
    for (const TableRow& row : file.read_table("/maze/summary")) {
      EXPECT_NE(std::get<std::string>(row.at(7)), "invalid");
    }
    EXPECT_GT(
        file.read_vector<double>("/maze/run_000/fits/ggk/k_0008_sigma3_brm_lambda1e-06/weights")
            .size(),
        0u);
  }
  for (const char* other : {"threads_2.h5", "threads_8.h5"}) {
    SCOPED_TRACE(std::string("threads_1.h5 vs ") + other);
    expect_identical_results(job, dir_ / "threads_1.h5", dir_ / other);
  }
}

TEST_F(JobRunnerTest, ComputeRunIsRepeatableAndMatchesTheStore) {
  const JobSpec job = load_job("job.toml", determinism_job(dir_ / "out.h5"));
  const RunRecord first = compute_run(job, 1);
  const RunRecord again = compute_run(job, 1);
  const RunRecord other = compute_run(job, 2);
  ASSERT_EQ(first.fits.size(), 8u);
  ASSERT_EQ(first.run, 1);
  EXPECT_EQ(first.samples.actions, again.samples.actions);
  EXPECT_NE(first.samples.actions, other.samples.actions) << "runs must draw distinct samples";

  run_job(job, options_for(job.output.file));
  const Hdf5File file = Hdf5File::open_read_only(job.output.file);
  for (std::size_t i = 0; i < first.fits.size(); ++i) {
    const FitRecord& fit = first.fits[i];
    const std::string group = "/maze/run_001/fits/" + fit_group_name(job, fit.point);
    SCOPED_TRACE(group);
    EXPECT_EQ(fit.status, again.fits[i].status);
    const std::vector<double> weights(fit.lspi.weights.data(),
                                      fit.lspi.weights.data() + fit.lspi.weights.size());
    const std::vector<double> weights_again(
        again.fits[i].lspi.weights.data(),
        again.fits[i].lspi.weights.data() + again.fits[i].lspi.weights.size());
    EXPECT_TRUE(same_bits(weights, weights_again));
    EXPECT_TRUE(same_bits(weights, file.read_vector<double>(group + "/weights")));
    EXPECT_EQ(fit.lspi.policy, file.read_vector<std::int32_t>(group + "/policy"));
    EXPECT_EQ(fit.centers, file.read_vector<std::int32_t>(group + "/centers"));
    EXPECT_EQ(fit.status, file.read_string_attribute(group, "status"));
  }
}

TEST_F(JobRunnerTest, ResumeOfACompleteFileComputesNothing) {
  const JobSpec job = load_job("job.toml", determinism_job(dir_ / "out.h5"));
  const RunSummary first = run_job(job, options_for(job.output.file));
  EXPECT_EQ(first.runs_computed, 3);
  EXPECT_EQ(first.runs_skipped, 0);
  const std::vector<TableRow> before =
      Hdf5File::open_read_only(job.output.file).read_table("/maze/summary");

  RunOptions resume = options_for(job.output.file);
  resume.resume = true;
  const RunSummary second = run_job(job, resume);
  EXPECT_EQ(second.runs_computed, 0);
  EXPECT_EQ(second.runs_skipped, 3);
  EXPECT_EQ(second.fits, 0);
  EXPECT_EQ(second.output, job.output.file);

  // Unchanged to the bit, fit_seconds included: the runs were not redone.
  const std::vector<TableRow> after =
      Hdf5File::open_read_only(job.output.file).read_table("/maze/summary");
  ASSERT_EQ(before.size(), after.size());
  ASSERT_EQ(after.size(), 3u * 8u);
  for (std::size_t r = 0; r < before.size(); ++r) {
    for (std::size_t c = 0; c < before[r].size(); ++c) {
      EXPECT_TRUE(same_cell(before[r][c], after[r][c])) << "row " << r << ", column " << c;
    }
  }
}

TEST_F(JobRunnerTest, ResumeRedoesIncompleteAndMissingRunsOnly) {
  std::string text = determinism_job(dir_ / "unused.h5");
  text.replace(text.find("runs = 3"), 8, "runs = 4");
  const JobSpec job = load_job("job.toml", text);
  const fs::path reference = dir_ / "reference.h5";
  const fs::path partial = dir_ / "partial.h5";
  run_job(job, options_for(reference));
  run_job(job, options_for(partial));

  // Simulate a sweep killed mid-way: run 1 written but never marked complete,
  // run 2 never written, no summary yet; runs 0 and 3 complete.
  std::vector<TableRow> run0_before, run3_before;
  {
    Hdf5File file = Hdf5File::open_read_write(partial);
    file.remove_attribute("/maze/run_001", "complete");
    file.remove("/maze/run_002");
    file.remove("/maze/summary");
    file.flush();
    run0_before = file.read_table("/maze/run_000/fit_metrics");
    run3_before = file.read_table("/maze/run_003/fit_metrics");
  }

  RunOptions resume = options_for(partial);
  resume.resume = true;
  const RunSummary summary = run_job(job, resume);
  EXPECT_EQ(summary.runs_computed, 2);
  EXPECT_EQ(summary.runs_skipped, 2);
  EXPECT_EQ(summary.fits, 2 * 8);

  expect_identical_results(job, reference, partial);
  EXPECT_EQ(summary_keys(partial, "maze"), every_fit_once(job));

  // The complete runs were kept as they were (their fit_seconds too).
  const Hdf5File file = Hdf5File::open_read_only(partial);
  const std::vector<TableRow> run0_after = file.read_table("/maze/run_000/fit_metrics");
  const std::vector<TableRow> run3_after = file.read_table("/maze/run_003/fit_metrics");
  ASSERT_EQ(run0_before.size(), run0_after.size());
  ASSERT_EQ(run3_before.size(), run3_after.size());
  for (std::size_t r = 0; r < run0_before.size(); ++r) {
    EXPECT_TRUE(same_cell(run0_before[r].back(), run0_after[r].back())) << "run 0 row " << r;
    EXPECT_TRUE(same_cell(run3_before[r].back(), run3_after[r].back())) << "run 3 row " << r;
  }
}

TEST_F(JobRunnerTest, ResumeOfAFileHoldingOnlyTheHeaderComputesEverything) {
  const JobSpec job = load_job("job.toml", determinism_job(dir_ / "out.h5"));
  const fs::path reference = dir_ / "reference.h5";
  run_job(job, options_for(reference));
  run_job(job, options_for(job.output.file));
  {
    Hdf5File file = Hdf5File::open_read_write(job.output.file);
    for (std::int32_t run = 0; run < job.runs; ++run) file.remove(run_group("maze", run));
    file.remove("/maze/summary");
    file.flush();
  }
  RunOptions resume = options_for(job.output.file);
  resume.resume = true;
  const RunSummary summary = run_job(job, resume);
  EXPECT_EQ(summary.runs_computed, 3);
  EXPECT_EQ(summary.runs_skipped, 0);
  expect_identical_results(job, reference, job.output.file);
}

TEST_F(JobRunnerTest, ResumeWithoutAnOutputFileStartsOne) {
  const JobSpec job = load_job("job.toml", determinism_job(dir_ / "out.h5"));
  RunOptions resume = options_for(job.output.file);
  resume.resume = true;
  const RunSummary summary = run_job(job, resume);
  EXPECT_EQ(summary.runs_computed, 3);
  EXPECT_EQ(summary_keys(job.output.file, "maze"), every_fit_once(job));
}

TEST_F(JobRunnerTest, ResumeRefusesTheResultsOfAnotherJob) {
  const std::string text = determinism_job(dir_ / "out.h5");
  const JobSpec job = load_job("job.toml", text);
  run_job(job, options_for(job.output.file));

  std::string other_text = text;
  other_text.replace(other_text.find("seed = 20240917"), 15, "seed = 20240918");
  const JobSpec other = load_job("other.toml", other_text);
  const std::string bytes = file_bytes(job.output.file);
  RunOptions resume = options_for(job.output.file);
  resume.resume = true;
  try {
    run_job(other, resume);
    FAIL() << "expected a UsageError";
  } catch (const UsageError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find(job.output.file.string()), std::string::npos) << message;
    EXPECT_NE(message.find("different job"), std::string::npos) << message;
  }
  EXPECT_EQ(file_bytes(job.output.file), bytes) << "a refused resume must not change the file";

  // The file still resumes under its own job.
  const RunSummary summary = run_job(job, resume);
  EXPECT_EQ(summary.runs_skipped, 3);
}

TEST_F(JobRunnerTest, ResumeRefusesAChangedMapFile) {
  // The determinism job with its map in a file next to the job file.
  std::string text = determinism_job(dir_ / "out.h5");
  const std::size_t map_begin = text.find("map = \"\"\"");
  const std::size_t map_end = text.find("\"\"\"", map_begin + 9) + 3;
  text.replace(map_begin, map_end - map_begin, "map_file = \"room.txt\"");
  const fs::path map = dir_ / "room.txt";
  std::ofstream(map, std::ios::binary) << kSmallMap;
  const JobSpec job = load_job("job.toml", text);
  ASSERT_EQ(job.inputs.size(), 1u);
  EXPECT_EQ(job.inputs[0].key, "maze.map_file");
  run_job(job, options_for(job.output.file));
  {
    const Hdf5File file = Hdf5File::open_read_only(job.output.file);
    EXPECT_EQ(file.read_string_attribute("/", "input:maze.map_file"), kSmallMap);
  }

  // The same job file over an edited map: the stored results are not its results.
  std::string edited = kSmallMap;
  edited.replace(edited.find("#.#."), 4, "#...");
  std::ofstream(map, std::ios::binary | std::ios::trunc) << edited;
  const JobSpec changed = load_job("job.toml", text);
  const std::string bytes = file_bytes(job.output.file);
  RunOptions resume = options_for(job.output.file);
  resume.resume = true;
  try {
    run_job(changed, resume);
    FAIL() << "expected a UsageError";
  } catch (const UsageError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find(job.inputs[0].path), std::string::npos) << message;
    EXPECT_NE(message.find("maze.map_file"), std::string::npos) << message;
  }
  EXPECT_EQ(file_bytes(job.output.file), bytes) << "a refused resume must not change the file";

  // Restored, it resumes.
  std::ofstream(map, std::ios::binary | std::ios::trunc) << kSmallMap;
  EXPECT_EQ(run_job(load_job("job.toml", text), resume).runs_skipped, 3);
}

TEST_F(JobRunnerTest, ExistingOutputNeedsResumeOrOverwrite) {
  const JobSpec job = load_job("job.toml", determinism_job(dir_ / "out.h5"));
  run_job(job, options_for(job.output.file));
  const std::string bytes = file_bytes(job.output.file);
  struct stat before {};
  ASSERT_EQ(::stat(job.output.file.c_str(), &before), 0);

  try {
    run_job(job, options_for(job.output.file));
    FAIL() << "expected a UsageError";
  } catch (const UsageError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find(job.output.file.string()), std::string::npos) << message;
    EXPECT_NE(message.find("--resume"), std::string::npos) << message;
    EXPECT_NE(message.find("--overwrite"), std::string::npos) << message;
  }
  struct stat after {};
  ASSERT_EQ(::stat(job.output.file.c_str(), &after), 0);
  EXPECT_EQ(file_bytes(job.output.file), bytes);
  EXPECT_EQ(before.st_mtim.tv_sec, after.st_mtim.tv_sec);
  EXPECT_EQ(before.st_mtim.tv_nsec, after.st_mtim.tv_nsec);
  EXPECT_EQ(before.st_ino, after.st_ino);

  // --overwrite replaces it with the same results.
  fs::copy_file(job.output.file, dir_ / "first.h5");
  RunOptions overwrite = options_for(job.output.file);
  overwrite.overwrite = true;
  EXPECT_EQ(run_job(job, overwrite).runs_computed, 3);
  expect_identical_results(job, dir_ / "first.h5", job.output.file);
}

TEST_F(JobRunnerTest, MissingOutputDirectoryIsAUsageError) {
  const JobSpec job = load_job("job.toml", determinism_job(dir_ / "out.h5"));
  EXPECT_THROW(run_job(job, options_for(dir_ / "missing" / "out.h5")), UsageError);
  EXPECT_FALSE(fs::exists(dir_ / "missing"));

  fs::create_directories(dir_ / "folder");
  RunOptions overwrite = options_for(dir_ / "folder");
  overwrite.overwrite = true;
  EXPECT_THROW(run_job(job, overwrite), UsageError);
  EXPECT_TRUE(fs::is_directory(dir_ / "folder"));
}

TEST_F(JobRunnerTest, ResumeOfAFileThatIsNotHdf5IsAUsageError) {
  const JobSpec job = load_job("job.toml", determinism_job(dir_ / "out.h5"));
  std::ofstream(job.output.file, std::ios::binary) << "not HDF5\n";
  RunOptions resume = options_for(job.output.file);
  resume.resume = true;
  try {
    run_job(job, resume);
    FAIL() << "expected a UsageError";
  } catch (const UsageError& error) {
    EXPECT_NE(std::string(error.what()).find(job.output.file.string()), std::string::npos)
        << error.what();
  }
  EXPECT_EQ(file_bytes(job.output.file), "not HDF5\n");
}

TEST_F(JobRunnerTest, TooManyKernelsIsAnInvalidFitAndTheOthersStillRun) {
  // 27 states: 50 kernels exceed every run's sample graph.
  std::string text = determinism_job(dir_ / "out.h5");
  text.replace(text.find("kernels = [4, 8]"), 16, "kernels = [4, 50]");
  const JobSpec job = load_job("job.toml", text);
  const std::vector<SweepPoint> points = expand_sweep(job);

  const RunRecord record = compute_run(job, 0);
  ASSERT_EQ(record.fits.size(), points.size());
  std::int32_t invalid = 0;
  for (const FitRecord& fit : record.fits) {
    SCOPED_TRACE(fit_group_name(job, fit.point));
    const std::map<std::string, double> metrics(fit.metrics.begin(), fit.metrics.end());
    if (fit.point.kernels == 50) {
      ++invalid;
      EXPECT_EQ(fit.status, "invalid");
      EXPECT_NE(fit.message.find("50 kernels"), std::string::npos) << fit.message;
      EXPECT_NE(fit.message.find("nodes"), std::string::npos) << fit.message;
      EXPECT_TRUE(std::isnan(metrics.at("success_rate")));
      EXPECT_TRUE(std::isnan(metrics.at("mean_steps_to_goal")));
      EXPECT_EQ(fit.lspi.weights.size(), 0);
      EXPECT_TRUE(fit.centers.empty());
    } else {
      EXPECT_NE(fit.status, "invalid");
      EXPECT_NE(fit.status, "solver_failed") << fit.message;
      EXPECT_TRUE(std::isfinite(metrics.at("success_rate")));
      EXPECT_EQ(fit.lspi.weights.size(), 4 * 4);
    }
    EXPECT_GT(metrics.at("graph_nodes"), 4.0);
    EXPECT_LE(metrics.at("graph_nodes"), 27.0);
  }
  EXPECT_EQ(invalid, 4);

  const RunSummary summary = run_job(job, options_for(job.output.file));
  EXPECT_EQ(summary.failed_fits, 3 * 4);
  const Hdf5File file = Hdf5File::open_read_only(job.output.file);
  const std::vector<TableColumn> columns = file.read_table_columns("/maze/summary");
  std::map<std::string, std::size_t> column;
  for (std::size_t c = 0; c < columns.size(); ++c) column[columns[c].name] = c;
  for (const TableRow& row : file.read_table("/maze/summary")) {
    const bool too_many = std::get<std::int32_t>(row.at(column.at("kernels"))) == 50;
    const std::string status = std::get<std::string>(row.at(column.at("status")));
    const double success = std::get<double>(row.at(column.at("success_rate")));
    EXPECT_EQ(status == "invalid", too_many) << status;
    EXPECT_EQ(std::isnan(success), too_many);
  }
  const std::string group = "/maze/run_002/fits/ogk/k_0050_sigma3_lstdq_lambda1e-06";
  EXPECT_EQ(file.read_string_attribute(group, "status"), "invalid");
  EXPECT_NE(file.read_string_attribute(group, "message").find("50 kernels"), std::string::npos);
  EXPECT_TRUE(std::isnan(file.read_double_attribute(group, "success_rate")));
  EXPECT_TRUE(file.read_vector<double>(group + "/weights").empty());
  EXPECT_FALSE(file.exists(group + "/steps_to_goal"));
  EXPECT_GT(
      file.read_vector<double>("/maze/run_002/fits/ogk/k_0004_sigma3_lstdq_lambda1e-06/weights")
          .size(),
      0u);
}

TEST_F(JobRunnerTest, FileFollowsTheDocumentedSchema) {
  const char* source_dir = std::getenv("GGK_SOURCE_DIR");
  if (source_dir == nullptr) GTEST_SKIP() << "GGK_SOURCE_DIR is not set (run through ctest)";
  const fs::path map_file = fs::path(source_dir) / "jobs" / "maps" / "four-rooms.txt";
  const std::string text = R"(name = "schema"
task = "maze"
runs = 2
seed = 99
[sweep]
basis = ["ggk", "ogk"]
kernels = [4, 8]
sigma = [5.0]
[maze]
map_file = ")" + map_file.string() +
                           R"("
series = 20
steps_per_series = 250
[output]
file = ")" + (dir_ / "schema.h5").string() +
                           R"("
)";
  const JobSpec job = load_job("schema.toml", text);
  const RunSummary summary = run_job(job, options_for(job.output.file));
  EXPECT_EQ(summary.output, job.output.file) << "no -o: the job's [output] file";
  const sims::maze::Maze maze(task_config_as<sims::maze::MazeConfig>(job).map_text);
  const std::vector<std::int32_t>& goals = maze.goal_states();
  ASSERT_EQ(goals.size(), 4u);

  const Hdf5File file = Hdf5File::open_read_only(job.output.file);
  EXPECT_EQ(file.read_string_attribute("/", "job"), text);
  EXPECT_FALSE(file.read_string_attribute("/", "ggk_version").empty());
  EXPECT_FALSE(file.read_string_attribute("/", "git").empty());
  EXPECT_TRUE(is_utc_timestamp(file.read_string_attribute("/", "created")))
      << file.read_string_attribute("/", "created");
  EXPECT_EQ(file.read_string_attribute("/", "task"), "maze");
  EXPECT_EQ(file.read_int64_attribute("/", "runs"), 2);

  const std::vector<std::string> metrics = discrete_metric_names();
  for (std::int32_t run = 0; run < 2; ++run) {
    const std::string group = run_group("maze", run);
    SCOPED_TRACE(group);
    ASSERT_TRUE(run_is_complete(file, "maze", run));

    const std::string s = group + "/samples";
    const RowMajorArray<double> obs = file.read_matrix<double>(s + "/observations");
    const RowMajorArray<double> next = file.read_matrix<double>(s + "/next_observations");
    const auto actions = file.read_vector<std::int32_t>(s + "/actions");
    const auto rewards = file.read_vector<double>(s + "/rewards");
    const auto terminals = file.read_vector<std::uint8_t>(s + "/terminals");
    EXPECT_EQ(obs.rows, 20 * 250);
    EXPECT_EQ(obs.cols, 2);
    EXPECT_EQ(next.rows, obs.rows);
    EXPECT_EQ(next.cols, 2);
    EXPECT_EQ(static_cast<std::int64_t>(actions.size()), obs.rows);
    EXPECT_EQ(static_cast<std::int64_t>(rewards.size()), obs.rows);
    EXPECT_EQ(static_cast<std::int64_t>(terminals.size()), obs.rows);
    for (std::size_t i = 0; i < actions.size(); ++i) {
      ASSERT_GE(actions[i], 0);
      ASSERT_LT(actions[i], maze.num_actions());
      ASSERT_EQ(rewards[i], terminals[i] ? 1.0 : 0.0) << "sample " << i;
    }

    // The graph: a symmetric CSR over every state, with the states' vectors.
    const CsrArrays graph = file.read_csr(group + "/graph", "weights");
    ASSERT_EQ(graph.rows, maze.num_states());
    ASSERT_EQ(graph.cols, maze.num_states());
    ASSERT_EQ(graph.indptr.size(), static_cast<std::size_t>(graph.rows) + 1);
    EXPECT_EQ(graph.indptr.front(), 0);
    EXPECT_EQ(graph.indptr.back(), static_cast<std::int64_t>(graph.indices.size()));
    ASSERT_EQ(graph.indices.size(), graph.data.size());
    EXPECT_GT(graph.indices.size(), 0u);
    std::map<std::pair<std::int32_t, std::int32_t>, double> edges;
    for (std::int64_t i = 0; i < graph.rows; ++i) {
      ASSERT_LE(graph.indptr[static_cast<std::size_t>(i)],
                graph.indptr[static_cast<std::size_t>(i) + 1]);
      for (auto e = graph.indptr[static_cast<std::size_t>(i)];
           e < graph.indptr[static_cast<std::size_t>(i) + 1]; ++e) {
        const std::int32_t j = graph.indices[static_cast<std::size_t>(e)];
        ASSERT_GE(j, 0);
        ASSERT_LT(j, graph.cols);
        EXPECT_NE(j, i) << "self loop";
        EXPECT_EQ(graph.data[static_cast<std::size_t>(e)], 1.0) << "maze moves are unit steps";
        edges[{static_cast<std::int32_t>(i), j}] = graph.data[static_cast<std::size_t>(e)];
      }
    }
    for (const auto& [edge, weight] : edges) {
      const auto reverse = edges.find({edge.second, edge.first});
      ASSERT_NE(reverse, edges.end()) << edge.first << " -> " << edge.second << " has no reverse";
      EXPECT_EQ(reverse->second, weight);
    }
    const RowMajorArray<double> nodes = file.read_matrix<double>(group + "/graph/nodes");
    const kernels::RowMatrixXd states = maze.state_vectors();
    ASSERT_EQ(nodes.rows, maze.num_states());
    ASSERT_EQ(nodes.cols, 2);
    EXPECT_TRUE(std::equal(nodes.data.begin(), nodes.data.end(), states.data()));

    const std::vector<std::uint8_t> visited =
        file.read_vector<std::uint8_t>(group + "/graph/visited");
    ASSERT_EQ(visited.size(), static_cast<std::size_t>(maze.num_states()));
    std::vector<std::int32_t> visited_goals;
    for (std::int32_t g : goals) {
      if (visited[static_cast<std::size_t>(g)] == 1) visited_goals.push_back(g);
    }
    ASSERT_GE(visited_goals.size(), 1u) << "the samples must reach a goal";

    // One fit group per sweep point; the first centres are the goals.
    for (const char* basis : {"ggk", "ogk"}) {
      for (std::int32_t kernels : {4, 8}) {
        char name[64];
        std::snprintf(name, sizeof name, "%s/fits/%s/k_%04d_sigma5_brm_lambda1e-06", group.c_str(),
                      basis, kernels);
        const std::string fit = name;
        SCOPED_TRACE(fit);
        ASSERT_TRUE(file.exists(fit));
        EXPECT_EQ(file.read_string_attribute(fit, "basis"), basis);
        EXPECT_EQ(file.read_int64_attribute(fit, "kernels"), kernels);
        EXPECT_EQ(file.read_double_attribute(fit, "sigma"), 5.0);
        EXPECT_EQ(file.read_string_attribute(fit, "solver"), "brm");
        const auto centers = file.read_vector<std::int32_t>(fit + "/centers");
        ASSERT_EQ(centers.size(), static_cast<std::size_t>(kernels));
        // Visited goals first (the goal cell walled in by other goals is never
        // entered: episodes end on the first goal), then other visited states.
        ASSERT_GE(centers.size(), visited_goals.size());
        EXPECT_TRUE(std::equal(visited_goals.begin(), visited_goals.end(), centers.begin()))
            << "the first centres must be the visited goal states";
        for (std::size_t j = 0; j < centers.size(); ++j) {
          ASSERT_GE(centers[j], 0);
          ASSERT_LT(centers[j], maze.num_states());
          EXPECT_EQ(visited[static_cast<std::size_t>(centers[j])], 1) << "centre " << j;
          if (j >= visited_goals.size()) {
            EXPECT_FALSE(maze.is_goal(centers[j])) << "centre " << j;
          }
        }
        EXPECT_EQ(std::set<std::int32_t>(centers.begin(), centers.end()).size(), centers.size());
        EXPECT_EQ(file.read_vector<double>(fit + "/weights").size(),
                  static_cast<std::size_t>(kernels) * 4);
        EXPECT_EQ(file.read_vector<std::int32_t>(fit + "/policy").size(),
                  static_cast<std::size_t>(maze.num_states()));
        for (const std::string& metric : metrics) EXPECT_TRUE(file.has_attribute(fit, metric));
        EXPECT_EQ(file.read_vector<std::int32_t>(fit + "/steps_to_goal").size(),
                  static_cast<std::size_t>(maze.num_states()) - goals.size());
        EXPECT_EQ(file.read_vector<double>(fit + "/state_values").size(),
                  static_cast<std::size_t>(maze.num_states()));
      }
    }
    // The ggk and ogk fits of a run share its centres (paired comparison).
    EXPECT_EQ(
        file.read_vector<std::int32_t>(group + "/fits/ggk/k_0008_sigma5_brm_lambda1e-06/centers"),
        file.read_vector<std::int32_t>(group + "/fits/ogk/k_0008_sigma5_brm_lambda1e-06/centers"));
    EXPECT_EQ(file.read_table(group + "/fit_metrics").size(), 4u);
  }

  EXPECT_EQ(file.read_table_columns("/maze/summary"), summary_columns(metrics));
  EXPECT_EQ(summary_keys(job.output.file, "maze"), every_fit_once(job));
}

}  // namespace
}  // namespace ggk::engine
