#include "engine/job/job_file.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <any>
#include <array>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <gtest/gtest.h>

#include "engine/tasks/task_list.hpp"
#include "sims/maze/maze.hpp"
#include "sims/maze/maze_config.hpp"
#include "support/files.hpp"
#include "support/job_text.hpp"

namespace ggk::engine {
namespace {

namespace fs = std::filesystem;
using namespace test_support;

constexpr const char* kSmallMap =
    "#######\n"
    "#.....#\n"
    "#.###.#\n"
    "#....G#\n"
    "#######\n";

// A scratch folder per test: maps/small.txt, maps/four-rooms.txt (the default
// map file), maps/bad.txt, an output folder out/ and a regular file plain.txt.
class JobFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    scratch_ = std::make_unique<ScratchDir>("ggk-job-file");
    dir_ = scratch_->path();
    fs::create_directories(dir_ / "maps");
    fs::create_directories(dir_ / "out");
    write("maps/small.txt", kSmallMap);
    write("maps/four-rooms.txt", kSmallMap);
    write("maps/bad.txt", "#####\n#.x.#\n#..G#\n#####\n");
    write("plain.txt", "not a folder\n");
  }

  fs::path write(const std::string& name, const std::string& text) const {
    return write_file(dir_ / name, text);
  }
  // Writes a job file with %DIR% replaced by the scratch folder.
  fs::path write_job(const std::string& name, const std::string& text) const {
    return test_support::write_job(dir_, name, text);
  }
  // The JobError message the job raises, or a failure if it loads.
  std::string error_of(const std::string& text, const std::string& name = "bad.toml") const {
    const fs::path path = write_job(name, text);
    try {
      load_job_file(path, task_tables());
    } catch (const JobError& error) {
      return error.what();
    }
    ADD_FAILURE() << "expected a JobError for:\n" << text;
    return {};
  }

  std::unique_ptr<ScratchDir> scratch_;
  fs::path dir_;
};

constexpr const char* kFullJob = R"(# every key given
name = "full-job_1"
task = "maze"
runs = 4
seed = 12345

[sweep]
basis = ["ogk", "ggk"]
kernels = [16, 4, 8]
sigma = [2, 5.5]
solver = ["lstdq", "brm"]
lambda = [1e-6, 0]

[maze]
map_file = "maps/small.txt"
slip = 0.25
series = 7
steps_per_series = 300
test_max_steps = 60

[basis]
scheme = "copy"
truncation = 0.01

[lspi]
gamma = 0.95
max_iterations = 30
fold_duplicates = false
min_rcond = 1e-12
stopping = "weights"
weight_tolerance = 1e-4
evaluate_iterations = true
linear_algebra = "sparse"
ridge = "relative"

[output]
file = "%DIR%/out/full.h5"
compression = 0
store_matrices = true
)";

TEST_F(JobFileTest, ReadsEveryKey) {
  const fs::path path = write_job("full.toml", kFullJob);
  const JobSpec job = load_job_file(path, task_tables());
  EXPECT_EQ(job.name, "full-job_1");
  EXPECT_EQ(job.task, "maze");
  EXPECT_EQ(job.runs, 4);
  EXPECT_EQ(job.seed, 12345u);
  EXPECT_EQ(job.sweep.basis, (std::vector<KernelType>{KernelType::ogk, KernelType::ggk}));
  EXPECT_EQ(job.sweep.kernels, (std::vector<std::int32_t>{16, 4, 8}));
  EXPECT_EQ(job.sweep.sigma, (std::vector<double>{2.0, 5.5}));
  EXPECT_EQ(job.sweep.solver, (std::vector<kernels::LspiSolver>{kernels::LspiSolver::lstdq,
                                                                kernels::LspiSolver::brm}));
  EXPECT_EQ(job.sweep.lambda, (std::vector<double>{1e-6, 0.0}));

  ASSERT_TRUE(job.task_config.type() == typeid(sims::maze::MazeConfig));
  const auto& maze = task_config_as<sims::maze::MazeConfig>(job);
  EXPECT_EQ(maze.map_text, kSmallMap);
  EXPECT_EQ(maze.slip, 0.25);
  EXPECT_EQ(maze.series, 7);
  EXPECT_EQ(maze.steps_per_series, 300);
  EXPECT_EQ(maze.test_max_steps, 60);

  EXPECT_EQ(job.basis.scheme, kernels::BasisScheme::copy);
  EXPECT_EQ(job.basis.truncation, 0.01);
  EXPECT_EQ(job.lspi.gamma, 0.95);
  EXPECT_EQ(job.lspi.max_iterations, 30);
  EXPECT_FALSE(job.lspi.fold_duplicates);
  EXPECT_EQ(job.lspi.min_rcond, 1e-12);
  EXPECT_EQ(job.lspi.stopping, kernels::LspiStopping::weights_converged);
  EXPECT_EQ(job.lspi.weight_tolerance, 1e-4);
  EXPECT_TRUE(job.lspi.evaluate_iterations);
  EXPECT_EQ(job.lspi.linear_algebra, kernels::LinearAlgebra::sparse);
  EXPECT_EQ(job.lspi.ridge, kernels::RidgeScale::relative);
  EXPECT_EQ(job.output.file, dir_ / "out" / "full.h5");
  EXPECT_EQ(job.output.compression, 0);
  EXPECT_TRUE(job.output.store_matrices);

  EXPECT_EQ(job.source_file, path);
  EXPECT_EQ(job.source_text, substitute(kFullJob, "DIR", dir_.string()));
  EXPECT_FALSE(fs::exists(dir_ / "out" / "full.h5")) << "validation must not create the file";
}

TEST_F(JobFileTest, FillsDefaults) {
  const fs::path path = write_job("minimal.toml", R"(
name = "minimal"
task = "maze"
runs = 1
seed = 0
[sweep]
kernels = [8]
sigma = [5.0]
[output]
file = "%DIR%/out/minimal.h5"
)");
  const JobSpec job = load_job_file(path, task_tables());
  EXPECT_EQ(job.sweep.basis, (std::vector<KernelType>{KernelType::ggk, KernelType::ogk}));
  EXPECT_EQ(job.sweep.solver, (std::vector<kernels::LspiSolver>{kernels::LspiSolver::brm}));
  EXPECT_EQ(job.sweep.lambda, (std::vector<double>{1e-6}));

  const auto& maze = task_config_as<sims::maze::MazeConfig>(job);
  EXPECT_EQ(maze.map_text, kSmallMap) << "default map file: maps/four-rooms.txt beside the job";
  const sims::maze::MazeConfig defaults;
  EXPECT_EQ(maze.slip, 0.0);
  EXPECT_EQ(maze.series, defaults.series);
  EXPECT_EQ(maze.steps_per_series, defaults.steps_per_series);
  EXPECT_EQ(maze.test_max_steps, defaults.test_max_steps);

  EXPECT_EQ(job.basis.scheme, kernels::BasisScheme::shift);
  EXPECT_EQ(job.basis.truncation, 0.0);
  EXPECT_EQ(job.lspi.gamma, 0.9);
  EXPECT_EQ(job.lspi.max_iterations, 20);
  EXPECT_TRUE(job.lspi.fold_duplicates);
  EXPECT_EQ(job.lspi.min_rcond, 1e-14);
  EXPECT_EQ(job.lspi.stopping, kernels::LspiStopping::policy_unchanged);
  EXPECT_EQ(job.lspi.weight_tolerance, 1e-5);
  EXPECT_FALSE(job.lspi.evaluate_iterations);
  EXPECT_EQ(job.lspi.linear_algebra, kernels::LinearAlgebra::automatic);
  EXPECT_EQ(job.lspi.ridge, kernels::RidgeScale::absolute);
  EXPECT_EQ(job.output.compression, 4);
  EXPECT_FALSE(job.output.store_matrices);
}

TEST_F(JobFileTest, DefaultOutputFileIsNamedAfterTheJob) {
  const fs::path path = write_job("named.toml", R"(
name = "named"
task = "maze"
runs = 1
seed = 0
[sweep]
kernels = [8]
sigma = [5.0]
)");
  JobLoadOptions options;
  options.check_output = false;
  EXPECT_EQ(load_job_file(path, task_tables(), options).output.file, fs::path("results/named.h5"));
}

TEST_F(JobFileTest, InlineMap) {
  const fs::path path = write_job("inline.toml", R"(
name = "inline"
task = "maze"
runs = 1
seed = 0
[sweep]
kernels = [2]
sigma = [1.0]
[maze]
map = """
####
#.G#
####
"""
[output]
file = "%DIR%/out/inline.h5"
)");
  const JobSpec job = load_job_file(path, task_tables());
  const auto& maze = task_config_as<sims::maze::MazeConfig>(job);
  EXPECT_EQ(sims::maze::Maze(maze.map_text).num_states(), 2);
}

TEST_F(JobFileTest, CommandLineOutputFileReplacesTheJobs) {
  // The job's own output folder does not exist; the override's does.
  const fs::path path = write_job("override.toml", R"(
name = "override"
task = "maze"
runs = 1
seed = 0
[sweep]
kernels = [8]
sigma = [5.0]
[output]
file = "%DIR%/missing/override.h5"
)");
  EXPECT_THROW(load_job_file(path, task_tables()), JobError);
  JobLoadOptions options;
  options.output_file = dir_ / "out" / "cli.h5";
  EXPECT_EQ(load_job_file(path, task_tables(), options).output.file, dir_ / "out" / "cli.h5");

  options.output_file = dir_ / "nowhere" / "cli.h5";
  try {
    load_job_file(path, task_tables(), options);
    FAIL() << "expected a JobError";
  } catch (const JobError& error) {
    EXPECT_NE(std::string(error.what()).find("command line"), std::string::npos) << error.what();
    EXPECT_NE(std::string(error.what()).find("nowhere"), std::string::npos) << error.what();
  }
}

TEST_F(JobFileTest, UnreadableJobFile) {
  try {
    load_job_file(dir_ / "no-such-job.toml", task_tables());
    FAIL() << "expected a JobError";
  } catch (const JobError& error) {
    EXPECT_EQ(error.line(), 0);
    EXPECT_NE(std::string(error.what()).find("no-such-job.toml: cannot read the job file"),
              std::string::npos)
        << error.what();
  }
}

TEST_F(JobFileTest, ErrorCarriesFileLineColumnAndKey) {
  const fs::path path = write_job("bad.toml", R"(name = "x"
task = "maze"
runs = 1
seed = 0
[sweep]
kernels = [4, -3]
sigma = [1.0]
)");
  try {
    load_job_file(path, task_tables());
    FAIL() << "expected a JobError";
  } catch (const JobError& error) {
    EXPECT_EQ(error.file(), path.string());
    EXPECT_EQ(error.line(), 6);
    EXPECT_EQ(error.column(), 15);
    EXPECT_EQ(error.key_path(), "sweep.kernels");
    EXPECT_EQ(std::string(error.what()),
              path.string() + ":6:15: [sweep] kernels: expected an array of integers >= 1, got -3");
  }
}

TEST_F(JobFileTest, ReportsTheFirstUnknownKeyInFileOrder) {
  // toml++ sorts keys by name; the error must still name the one met first.
  const std::string message = error_of(R"(name = "x"
zzz = 1
aaa = 2
)");
  EXPECT_NE(message.find("bad.toml:2:1: zzz: unknown key"), std::string::npos) << message;
}

// Every malformed job below starts from kBadJobHeader (support/job_text.hpp), lines 1-9.
struct MalformedJob {
  std::string what;                   // the case, for failure messages
  std::string text;                   // the job file; %DIR% is the scratch folder
  std::vector<std::string> expected;  // substrings of the message: place, key, detail
};

// The parts of the message for an unknown task: every registered task is offered.
std::vector<std::string> unknown_task_message() {
  std::vector<std::string> parts = {"bad.toml:2:1: task: expected one of '", "got \"robot\""};
  for (const TaskTable& table : task_tables()) parts.push_back("'" + std::string(table.name) + "'");
  return parts;
}

std::vector<MalformedJob> malformed_jobs() {
  const std::string h = kBadJobHeader;
  return {
      {"syntax error", h + "[lspi]\ngamma = 0.9 0.8\n", {"bad.toml:11:13:", "TOML syntax error"}},
      {"duplicate TOML key",
       header_with(4, "seed = 1\nseed = 2"),
       {"bad.toml:5:", "TOML syntax error", "'seed'"}},
      {"unknown top-level key",
       "rusn = 2\n" + h,
       {"bad.toml:1:1: rusn: unknown key; did you mean 'runs'?"}},
      {"unknown table",
       h + "[robot]\nlinks = 2\n",
       {"bad.toml:10:", "robot: unknown key", "'lspi'"}},
      {"unknown key in [lspi] with suggestion",
       h + "[lspi]\ngama = 0.9\n",
       {"bad.toml:11:1: [lspi] gama: unknown key; did you mean 'gamma'?"}},
      {"unknown key in [sweep]",
       header_with(6, "kernel = [4, 8]"),
       {"bad.toml:6:1: [sweep] kernel: unknown key; did you mean 'kernels'?"}},
      {"unknown key in [maze]",
       h + "[maze]\nmax_steps = 10\n",
       {"bad.toml:11:1: [maze] max_steps: unknown key"}},
      {"runs wrong type",
       header_with(3, "runs = \"2\""),
       {"bad.toml:3:1: runs: expected an integer >= 1, got \"2\""}},
      {"runs = 0",
       header_with(3, "runs = 0"),
       {"bad.toml:3:1: runs: expected an integer >= 1, got 0"}},
      {"runs = -1",
       header_with(3, "runs = -1"),
       {"bad.toml:3:1: runs: expected an integer >= 1, got -1"}},
      {"runs too large",
       header_with(3, "runs = 3000000000"),
       {"bad.toml:3:1: runs:", "2147483647", "got 3000000000"}},
      {"seed < 0",
       header_with(4, "seed = -5"),
       {"bad.toml:4:1: seed: expected an integer >= 0, got -5"}},
      {"bad name", header_with(1, "name = \"my job\""), {"bad.toml:1:1: name:", "\"my job\""}},
      {"empty sweep axis",
       header_with(6, "kernels = []"),
       {"bad.toml:6:1: [sweep] kernels:", "got an empty array"}},
      {"duplicate sweep value",
       header_with(6, "kernels = [4, 8, 4]"),
       {"bad.toml:6:18: [sweep] kernels: duplicate value 4", "first given at line 6, column 12"}},
      {"kernels = 0",
       header_with(6, "kernels = [4, 0]"),
       {"bad.toml:6:15: [sweep] kernels:", "integers >= 1, got 0"}},
      {"kernels float",
       header_with(6, "kernels = [4, 2.5]"),
       {"bad.toml:6:15: [sweep] kernels:", "got 2.5"}},
      {"sweep axis not an array",
       header_with(7, "sigma = 2.0"),
       {"bad.toml:7:1: [sweep] sigma:", "write [2.0]"}},
      {"sigma = 0",
       header_with(7, "sigma = [0.0]"),
       {"bad.toml:7:10: [sweep] sigma: expected an array of numbers > 0.0, got 0.0"}},
      {"sigma < 0", header_with(7, "sigma = [-1]"), {"bad.toml:7:10: [sweep] sigma:", "got -1"}},
      {"sigma nan", header_with(7, "sigma = [nan]"), {"bad.toml:7:10: [sweep] sigma:", "got nan"}},
      {"lambda < 0",
       header_with(8, "lambda = [-1e-3]\n[output]"),
       {"bad.toml:8:11: [sweep] lambda:", "numbers >= 0.0, got -0.001"}},
      {"unknown basis",
       header_with(8, "basis = [\"ggk\", \"gkk\"]\n[output]"),
       {"bad.toml:8:17: [sweep] basis:", "\"gkk\"", "did you mean 'ggk'?"}},
      {"unknown solver",
       header_with(8, "solver = [\"lstd\"]\n[output]"),
       {"bad.toml:8:11: [sweep] solver:", "did you mean 'lstdq'?"}},
      {"unknown task", header_with(2, "task = \"robot\""), unknown_task_message()},
      {"missing required key in [sweep]",
       header_without(7),
       {"bad.toml:5:1: [sweep] sigma: required key is missing"}},
      {"missing required top-level key",
       header_without(3),
       {"bad.toml: runs: required key is missing"}},
      {"table of wrong type", "lspi = 3\n" + h, {"bad.toml:1:1: lspi: expected a table, got 3"}},
      {"gamma = 1",
       h + "[lspi]\ngamma = 1.0\n",
       {"bad.toml:11:1: [lspi] gamma: expected a number in [0.0, 1.0), got 1.0"}},
      {"gamma wrong type",
       h + "[lspi]\ngamma = true\n",
       {"bad.toml:11:1: [lspi] gamma:", "got true"}},
      {"max_iterations = 0",
       h + "[lspi]\nmax_iterations = 0\n",
       {"bad.toml:11:1: [lspi] max_iterations:", "got 0"}},
      {"max_iterations that never ends",
       h + "[lspi]\nmax_iterations = 2147483647\n",
       {"bad.toml:11:1: [lspi] max_iterations: expected an integer in [1, 1000], got 2147483647"}},
      {"max_iterations just past its range",
       h + "[lspi]\nmax_iterations = 1001\n",
       {"bad.toml:11:1: [lspi] max_iterations: expected an integer in [1, 1000], got 1001"}},
      {"min_rcond = 0", h + "[lspi]\nmin_rcond = 0\n", {"bad.toml:11:1: [lspi] min_rcond:"}},
      {"stopping unknown",
       h + "[lspi]\nstopping = \"weight\"\n",
       {"bad.toml:11:1: [lspi] stopping:", "\"weight\"", "weights"}},
      {"ridge unknown",
       h + "[lspi]\nridge = \"scaled\"\n",
       {"bad.toml:11:1: [lspi] ridge:", "\"scaled\"", "relative"}},
      {"linear_algebra unknown",
       h + "[lspi]\nlinear_algebra = \"lapack\"\n",
       {"bad.toml:11:1: [lspi] linear_algebra:", "\"lapack\"", "dense"}},
      {"weight_tolerance < 0",
       h + "[lspi]\nweight_tolerance = -1e-5\n",
       {"bad.toml:11:1: [lspi] weight_tolerance:", "got -1e-05"}},
      {"evaluate_iterations wrong type",
       h + "[lspi]\nevaluate_iterations = 1\n",
       {"bad.toml:11:1: [lspi] evaluate_iterations: expected true or false, got 1"}},
      {"fold_duplicates wrong type",
       h + "[lspi]\nfold_duplicates = \"yes\"\n",
       {"bad.toml:11:1: [lspi] fold_duplicates: expected true or false, got \"yes\""}},
      {"slip = 1",
       h + "[maze]\nslip = 1\n",
       {"bad.toml:11:1: [maze] slip: expected a number in [0.0, 1.0), got 1"}},
      {"series = 0", h + "[maze]\nseries = 0\n", {"bad.toml:11:1: [maze] series:", "got 0"}},
      {"test_max_steps wrong type",
       h + "[maze]\ntest_max_steps = \"100\"\n",
       {"bad.toml:11:1: [maze] test_max_steps:", "got \"100\""}},
      {"too many samples",
       h + "[maze]\nseries = 100000\nsteps_per_series = 100000\n",
       {"bad.toml:12:1: [maze] steps_per_series:", "10000000000 samples"}},
      {"truncation < 0",
       h + "[basis]\ntruncation = -0.1\n",
       {"bad.toml:11:1: [basis] truncation:", "got -0.1"}},
      {"unknown scheme",
       h + "[basis]\nscheme = \"shfit\"\n",
       {"bad.toml:11:1: [basis] scheme:", "did you mean 'shift'?"}},
      {"missing map file",
       h + "[maze]\nmap_file = \"maps/nope.txt\"\n",
       {"bad.toml:11:1: [maze] map_file:", "maps/nope.txt", "does not exist"}},
      {"map file is a folder",
       h + "[maze]\nmap_file = \"maps\"\n",
       {"bad.toml:11:1: [maze] map_file:", "is a directory"}},
      {"both map and map_file",
       h + "[maze]\nmap_file = \"maps/small.txt\"\nmap = \"G.\"\n",
       {"bad.toml:12:1: [maze] map:", "not both"}},
      {"malformed map file",
       h + "[maze]\nmap_file = \"maps/bad.txt\"\n",
       {"bad.toml:11:1: [maze] map_file:", "maps/bad.txt", "row 2, column 3", "'x'"}},
      {"malformed inline map",
       h + "[maze]\nmap = \"\"\"\n#.G\n#..#\n\"\"\"\n",
       {"bad.toml:11:1: [maze] map:", "row 2, column 4"}},
      {"map without goal",
       h + "[maze]\nmap = \"...\"\n",
       {"bad.toml:11:1: [maze] map:", "no goal"}},
      {"output directory missing",
       header_with(9, "file = \"%DIR%/missing/bad.h5\""),
       {"bad.toml:9:1: [output] file:", "missing", "does not exist"}},
      {"output directory is a regular file",
       header_with(9, "file = \"%DIR%/plain.txt/bad.h5\""),
       {"bad.toml:9:1: [output] file:", "plain.txt", "is not a directory"}},
      {"output file is a folder",
       header_with(9, "file = \"%DIR%/out\""),
       {"bad.toml:9:1: [output] file:", "is a directory"}},
      {"compression = 12",
       h + "compression = 12\n",
       {"bad.toml:10:1: [output] compression: expected an integer in [0, 9], got 12"}},
      {"store_matrices wrong type",
       h + "store_matrices = 1\n",
       {"bad.toml:10:1: [output] store_matrices:", "got 1"}},
  };
}

TEST_F(JobFileTest, RejectsMalformedJobs) {
  const std::vector<MalformedJob> cases = malformed_jobs();
  ASSERT_GE(cases.size(), 20u);
  for (const MalformedJob& job : cases) {
    const std::string message = error_of(job.text);
    for (const std::string& part : job.expected) {
      EXPECT_NE(message.find(part), std::string::npos)
          << "case '" << job.what << "': the message\n  " << message << "\nlacks\n  " << part;
    }
  }
}

TEST_F(JobFileTest, MissingSweepTable) {
  const std::string message = error_of(R"(name = "bad"
task = "maze"
runs = 2
seed = 1
)");
  EXPECT_NE(message.find("bad.toml: sweep: required table [sweep] is missing"), std::string::npos)
      << message;
}

TEST_F(JobFileTest, RejectsUnwritableOutputDirectory) {
  if (::geteuid() == 0) GTEST_SKIP() << "root may write to any directory; see the plain.txt case";
  fs::create_directories(dir_ / "locked");
  fs::permissions(dir_ / "locked", fs::perms::owner_read | fs::perms::owner_exec);
  const std::string message = error_of(header_with(9, "file = \"%DIR%/locked/bad.h5\""));
  EXPECT_NE(message.find("bad.toml:9:1: [output] file:"), std::string::npos) << message;
  EXPECT_NE(message.find("not writable"), std::string::npos) << message;
}

// The job files shipped in jobs/ are valid (output directories aside, which
// depend on where ggk runs).
TEST(ShippedJobFiles, AreValid) {
  const char* source_dir = std::getenv("GGK_SOURCE_DIR");
  if (source_dir == nullptr) GTEST_SKIP() << "GGK_SOURCE_DIR is not set (run through ctest)";
  JobLoadOptions options;
  options.check_output = false;
  for (const char* name : {"quick", "ci", "maze"}) {
    SCOPED_TRACE(name);
    const fs::path path = fs::path(source_dir) / "jobs" / (std::string(name) + ".toml");
    const JobSpec job = load_job_file(path, task_tables(), options);
    EXPECT_EQ(job.name, name);
    EXPECT_EQ(job.task, "maze");
    EXPECT_NO_THROW(sims::maze::Maze(task_config_as<sims::maze::MazeConfig>(job).map_text));
  }
}

// The reader is handed the tasks' tables and names none itself: a task the engine
// does not register works like the built-in ones, with no change to the reader
// (the "adding a task" steps of engine/README.md).
struct ToyConfig {
  std::int64_t size = 1;
};
constexpr std::array<std::string_view, 1> kToyKeys = {"size"};
std::any parse_toy_table(const TomlTableReader& job, const fs::path&, std::vector<JobInput>&) {
  const TomlTableReader table = job.subtable_or_empty("toy", kToyKeys);
  return ToyConfig{table.integer("size", {1, 100}, 1)};
}
constexpr std::array<TaskTable, 1> kToyTasks = {{{"toy", parse_toy_table}}};

std::string toy_job(const std::string& task, const std::string& tables) {
  return "name = \"toy\"\ntask = \"" + task + "\"\nruns = 1\nseed = 0\n[sweep]\nkernels = [2]\n" +
         "sigma = [1]\n" + tables;
}
std::string toy_error(const std::string& text, std::span<const TaskTable> tasks) {
  try {
    parse_job(text, "toy.toml", tasks, no_output_check());
  } catch (const JobError& error) {
    return error.what();
  }
  ADD_FAILURE() << "expected a JobError for:\n" << text;
  return {};
}

TEST(TaskTables, AnUnregisteredTaskReadsItsOwnTable) {
  const JobSpec job =
      parse_job(toy_job("toy", "[toy]\nsize = 7\n"), "toy.toml", kToyTasks, no_output_check());
  EXPECT_EQ(job.task, "toy");
  EXPECT_EQ(task_config_as<ToyConfig>(job).size, 7);
  EXPECT_THROW(task_config_as<sims::maze::MazeConfig>(job), std::logic_error);
  // The reader's own checks apply to the toy table too.
  const std::string range = toy_error(toy_job("toy", "[toy]\nsize = 700\n"), kToyTasks);
  EXPECT_NE(range.find("toy.toml:9:1: [toy] size:"), std::string::npos) << range;
  const std::string spelling = toy_error(toy_job("toy", "[toy]\nsise = 7\n"), kToyTasks);
  EXPECT_NE(spelling.find("did you mean 'size'"), std::string::npos) << spelling;
}

TEST(TaskTables, OnlyTheGivenTasksAreKnown) {
  // The maze is not among the tasks handed over: task = "maze" and [maze] are errors.
  const std::string unknown = toy_error(toy_job("maze", ""), kToyTasks);
  EXPECT_NE(unknown.find("task:"), std::string::npos) << unknown;
  EXPECT_NE(unknown.find("toy"), std::string::npos) << unknown;
  const std::string table = toy_error(toy_job("toy", "[maze]\nslip = 0\n"), kToyTasks);
  EXPECT_NE(table.find("maze: unknown key"), std::string::npos) << table;
  // With the registered tasks and the toy, a [maze] table in a toy job is refused.
  std::vector<TaskTable> both(task_tables().begin(), task_tables().end());
  both.push_back(kToyTasks[0]);
  const std::string foreign = toy_error(toy_job("toy", "[maze]\nslip = 0\n"), both);
  EXPECT_NE(foreign.find("belongs to task 'maze'"), std::string::npos) << foreign;
  const std::string misspelt = toy_error(toy_job("toy", "[toi]\nsize = 2\n"), both);
  EXPECT_NE(misspelt.find("did you mean 'toy'"), std::string::npos) << misspelt;
}

TEST(TaskTables, ATaskNamedLikeACommonKeyIsAProgrammerError) {
  const std::array<TaskTable, 1> clash = {{{"sweep", parse_toy_table}}};
  EXPECT_THROW(parse_job(toy_job("sweep", ""), "toy.toml", clash, no_output_check()),
               std::logic_error);
}

// The list in task_list.cpp is the one place a task is registered: its tables
// are the job reader's, each found by its name, distinct, and complete.
TEST(TaskTables, EveryRegisteredTaskIsFoundByItsTable) {
  std::vector<std::string_view> names;
  for (const TaskTable& table : task_tables()) names.push_back(table.name);
  ASSERT_EQ(names.size(), registered_tasks().size());
  ASSERT_FALSE(names.empty());
  for (std::size_t i = 0; i < names.size(); ++i) {
    EXPECT_EQ(std::count(names.begin(), names.end(), names[i]), 1) << names[i];
    EXPECT_EQ(registered_tasks()[i].table.name, names[i]);
    const TaskDefinition* task = find_task(names[i]);
    ASSERT_NE(task, nullptr) << names[i];
    EXPECT_NE(task->table.parse, nullptr) << names[i];
    EXPECT_NE(task->compute_run, nullptr) << names[i];
  }
  EXPECT_EQ(find_task("toy"), nullptr);
}

// [pvf]: the defaults (jobs/README.md) and every value; a job with neither the
// basis nor the table records no pvf.* key (older results files resume).
TEST(PvfTable, DefaultsValuesAndTheResolvedConfiguration) {
  const char* source_dir = std::getenv("GGK_SOURCE_DIR");
  if (source_dir == nullptr) GTEST_SKIP() << "GGK_SOURCE_DIR is not set (run through ctest)";
  // Read as a file of jobs/, whose maps the maze's default map_file names.
  const fs::path source = fs::path(source_dir) / "jobs" / "pvf.toml";
  const auto parse = [&source](const std::string& text) { return parse_unchecked(text, source); };
  const std::string header = substitute(kBadJobHeader, "DIR", "/tmp");
  const JobSpec plain = parse(header);
  EXPECT_FALSE(plain.resolved.contains("pvf.laplacian"));
  EXPECT_FALSE(plain.resolved.contains("pvf.edge_weights"));

  const JobSpec defaults = parse(with_line(header, 6, "kernels = [4, 8]\nbasis = [\"pvf\"]"));
  EXPECT_EQ(defaults.sweep.basis, (std::vector<KernelType>{KernelType::pvf}));
  EXPECT_EQ(defaults.pvf.laplacian, kernels::LaplacianKind::normalized);
  EXPECT_EQ(defaults.pvf.edge_weights, kernels::EdgeAffinity::unit);
  EXPECT_EQ(defaults.pvf.actions, kernels::BasisScheme::copy);
  EXPECT_TRUE(defaults.resolved.contains("pvf.laplacian"));
  EXPECT_TRUE(defaults.resolved.contains("pvf.actions"));

  const JobSpec set = parse(header +
                            "[pvf]\nlaplacian = \"combinatorial\"\nedge_weights = \"gaussian\"\n"
                            "actions = \"shift\"\n");
  EXPECT_EQ(set.pvf.laplacian, kernels::LaplacianKind::combinatorial);
  EXPECT_EQ(set.pvf.edge_weights, kernels::EdgeAffinity::gaussian);
  EXPECT_EQ(set.pvf.actions, kernels::BasisScheme::shift);
  EXPECT_EQ(parse(header + "[pvf]\nedge_weights = \"distance\"\n").pvf.edge_weights,
            kernels::EdgeAffinity::distance);

  // A bad value or key names it, with its line.
  try {
    parse(header + "[pvf]\nlaplacian = \"random_walk\"\n");
    FAIL() << "accepted laplacian = \"random_walk\"";
  } catch (const JobError& error) {
    EXPECT_NE(std::string(error.what()).find("laplacian"), std::string::npos) << error.what();
    EXPECT_NE(std::string(error.what()).find("combinatorial"), std::string::npos) << error.what();
  }
  EXPECT_THROW(parse(header + "[pvf]\nedge_weight = \"unit\"\n"), JobError);
}

}  // namespace
}  // namespace ggk::engine
