// The ggk command line, run as a separate process: exit statuses, messages, no
// output on errors, and a sweep killed with SIGKILL that --resume finishes.

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "engine/hdf5/hdf5_file.hpp"
#include "engine/job/job_file.hpp"
#include "engine/job/sweep.hpp"
#include "engine/store/process_state.hpp"
#include "engine/store/run_store.hpp"
#include "engine/tasks/task_list.hpp"
#include "support/files.hpp"
#include "support/ggk_binary.hpp"
#include "support/job_text.hpp"
#include "support/results_compare.hpp"

extern char** environ;

namespace ggk::engine {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;
using namespace test_support;

constexpr const char* kScratchMap =
    "#######\n"
    "#.....#\n"
    "#.###.#\n"
    "#....G#\n"
    "#######\n";

// A scratch folder per test: maps/four-rooms.txt (a small map, the default
// map_file of a job in the folder), out/ for results, plain.txt.
class CliTest : public GgkBinaryTest {
 protected:
  void SetUp() override {
    GgkBinaryTest::SetUp();
    if (IsSkipped() || HasFatalFailure()) return;
    fs::create_directories(dir_ / "maps");
    fs::create_directories(dir_ / "out");
    write("maps/four-rooms.txt", kScratchMap);
    write("plain.txt", "not a results file\n");
  }

  // Writes `text` (with %DIR% replaced by the scratch folder) to <dir>/<name>.
  fs::path write(const std::string& name, const std::string& text) const {
    return write_job(dir_, name, text);
  }
};

struct MalformedJobCase {
  std::string what;
  std::string text;
  std::string place;  // "bad.toml:LINE:"
  std::string key;    // how the message names the key (or the error, for syntax errors)
};

std::vector<MalformedJobCase> malformed_job_cases() {
  const std::string h = kBadJobHeader;
  return {
      {"syntax error", h + "[lspi]\ngamma = 0.9 0.8\n", "bad.toml:11:", "TOML syntax error"},
      {"duplicate key", header_with(4, "seed = 1\nseed = 2"), "bad.toml:5:", "'seed'"},
      {"unknown top-level key", "rusn = 2\n" + h, "bad.toml:1:", "rusn: unknown key"},
      {"unknown table", h + "[robot]\nlinks = 2\n", "bad.toml:10:", "robot: unknown key"},
      {"unknown key in [lspi]", h + "[lspi]\ngama = 0.9\n", "bad.toml:11:", "[lspi] gama"},
      {"unknown key in [sweep]", header_with(6, "kernel = [4]"), "bad.toml:6:", "[sweep] kernel"},
      {"unknown key in [maze]", h + "[maze]\nmax_steps = 1\n", "bad.toml:11:", "[maze] max_steps"},
      {"runs wrong type", header_with(3, "runs = \"2\""), "bad.toml:3:", "runs:"},
      {"runs = 0", header_with(3, "runs = 0"), "bad.toml:3:", "runs:"},
      {"seed < 0", header_with(4, "seed = -5"), "bad.toml:4:", "seed:"},
      {"bad name", header_with(1, "name = \"my job\""), "bad.toml:1:", "name:"},
      {"empty sweep axis", header_with(6, "kernels = []"), "bad.toml:6:", "[sweep] kernels"},
      {"duplicate sweep value", header_with(6, "kernels = [4, 4]"),
       "bad.toml:6:", "[sweep] kernels"},
      {"kernels float", header_with(6, "kernels = [2.5]"), "bad.toml:6:", "[sweep] kernels"},
      {"sweep axis not an array", header_with(7, "sigma = 2.0"), "bad.toml:7:", "[sweep] sigma"},
      {"sigma = 0", header_with(7, "sigma = [0.0]"), "bad.toml:7:", "[sweep] sigma"},
      {"lambda < 0", header_with(8, "lambda = [-1e-3]\n[output]"), "bad.toml:8:", "[sweep] lambda"},
      {"unknown basis", header_with(8, "basis = [\"gkk\"]\n[output]"),
       "bad.toml:8:", "[sweep] basis"},
      {"unknown solver", header_with(8, "solver = [\"lstd\"]\n[output]"),
       "bad.toml:8:", "[sweep] solver"},
      {"unknown task", header_with(2, "task = \"robot\""), "bad.toml:2:", "task:"},
      {"missing required key", header_without(7), "bad.toml:5:", "[sweep] sigma"},
      {"table of wrong type", "lspi = 3\n" + h, "bad.toml:1:", "lspi:"},
      {"gamma = 1", h + "[lspi]\ngamma = 1.0\n", "bad.toml:11:", "[lspi] gamma"},
      {"fold_duplicates wrong type", h + "[lspi]\nfold_duplicates = \"yes\"\n",
       "bad.toml:11:", "[lspi] fold_duplicates"},
      {"slip = 1", h + "[maze]\nslip = 1\n", "bad.toml:11:", "[maze] slip"},
      {"unknown scheme", h + "[basis]\nscheme = \"shfit\"\n", "bad.toml:11:", "[basis] scheme"},
      {"missing map file", h + "[maze]\nmap_file = \"maps/nope.txt\"\n",
       "bad.toml:11:", "[maze] map_file"},
      {"both map and map_file", h + "[maze]\nmap_file = \"maps/four-rooms.txt\"\nmap = \"G.\"\n",
       "bad.toml:12:", "[maze] map"},
      {"malformed inline map", h + "[maze]\nmap = \"\"\"\n#.G\n#..#\n\"\"\"\n",
       "bad.toml:11:", "[maze] map"},
      {"output directory missing", header_with(9, "file = \"%DIR%/missing/bad.h5\""),
       "bad.toml:9:", "[output] file"},
      {"output directory is a regular file", header_with(9, "file = \"%DIR%/plain.txt/bad.h5\""),
       "bad.toml:9:", "[output] file"},
      {"output file is a folder", header_with(9, "file = \"%DIR%/out\""),
       "bad.toml:9:", "[output] file"},
      {"compression = 12", h + "compression = 12\n", "bad.toml:10:", "[output] compression"},
  };
}

TEST_F(CliTest, MalformedJobsExitWithStatus2AndWriteNothing) {
  std::vector<MalformedJobCase> cases = malformed_job_cases();
  if (::geteuid() != 0) {  // root writes anywhere
    fs::create_directories(dir_ / "locked");
    fs::permissions(dir_ / "locked", fs::perms::owner_read | fs::perms::owner_exec);
    cases.push_back({"unwritable output directory",
                     header_with(9, "file = \"%DIR%/locked/bad.h5\""),
                     "bad.toml:9:", "[output] file"});
  }
  ASSERT_GE(cases.size(), 20u);
  for (const MalformedJobCase& job : cases) {
    SCOPED_TRACE(job.what);
    const fs::path path = write("bad.toml", job.text);
    for (const char* command : {"validate", "run"}) {
      SCOPED_TRACE(command);
      const Outcome outcome = ggk({command, path.string()});
      EXPECT_EQ(outcome.status, kUserError) << outcome.err;
      EXPECT_TRUE(contains(outcome.err, "ggk: error: "));
      EXPECT_TRUE(contains(outcome.err, path.string() + job.place.substr(8)));
      EXPECT_TRUE(contains(outcome.err, job.key));
      EXPECT_TRUE(outcome.out.empty()) << outcome.out;
      EXPECT_TRUE(fs::is_empty(dir_ / "out")) << "an invalid job wrote an output file";
      EXPECT_FALSE(fs::exists(dir_ / "missing"));
      EXPECT_FALSE(fs::exists(dir_ / "results"));
    }
  }
}

TEST_F(CliTest, UnreadableJobFileIsAUserError) {
  const Outcome outcome = ggk({"run", (dir_ / "nope.toml").string()});
  EXPECT_EQ(outcome.status, kUserError);
  EXPECT_TRUE(contains(outcome.err, (dir_ / "nope.toml").string()));
  EXPECT_TRUE(fs::is_empty(dir_ / "out"));
}

TEST_F(CliTest, BadCommandLinesExitWithStatus2) {
  const fs::path job = write("good.toml", kBadJobHeader);
  const std::vector<std::vector<std::string>> cases = {
      {},                                                                 // no subcommand
      {"frobnicate"},                                                     // unknown subcommand
      {"run"},                                                            // no job
      {"run", job.string(), "--frobnicate"},                              // unknown option
      {"run", job.string(), "-j", "0"},                                   // out of range
      {"run", job.string(), "-j", "many"},                                // not a number
      {"run", job.string(), "--resume", "--overwrite"},                   // exclusive flags
      {"run", job.string(), "-o", (dir_ / "missing" / "x.h5").string()},  // -o folder missing
      {"validate"},
      {"info"},
  };
  for (const auto& args : cases) {
    std::string line = "ggk";
    for (const std::string& arg : args) line += " " + arg;
    SCOPED_TRACE(line);
    const Outcome outcome = ggk(args);
    EXPECT_EQ(outcome.status, kUserError) << outcome.out << outcome.err;
    EXPECT_FALSE(outcome.err.empty());
  }
  EXPECT_TRUE(fs::is_empty(dir_ / "out"));
  EXPECT_FALSE(fs::exists(dir_ / "missing"));
  EXPECT_TRUE(contains(ggk({"run", job.string(), "--resume", "--overwrite"}).err, "exclude"));
  EXPECT_TRUE(contains(ggk({"run", job.string(), "-o", (dir_ / "missing" / "x.h5").string()}).err,
                       "missing"));
  EXPECT_EQ(ggk({"--help"}).status, 0);
}

TEST_F(CliTest, OutputThatIsNoResultsFileIsAUserError) {
  const fs::path job = write("good.toml", kBadJobHeader);
  const fs::path plain = dir_ / "plain.txt";
  const std::string bytes = file_bytes(plain);
  for (const char* flag : {"", "--resume"}) {
    SCOPED_TRACE(flag);
    std::vector<std::string> args = {"run", job.string(), "-q", "-o", plain.string()};
    if (*flag != '\0') args.emplace_back(flag);
    const Outcome outcome = ggk(args);
    EXPECT_EQ(outcome.status, kUserError) << outcome.err;
    EXPECT_TRUE(contains(outcome.err, "ggk: error: "));
    EXPECT_TRUE(contains(outcome.err, plain.string()));
    EXPECT_EQ(file_bytes(plain), bytes);
  }
  for (const char* flag : {"", "--resume", "--overwrite"}) {
    SCOPED_TRACE(flag);
    std::vector<std::string> args = {"run", job.string(), "-q", "-o", (dir_ / "out").string()};
    if (*flag != '\0') args.emplace_back(flag);
    const Outcome outcome = ggk(args);
    EXPECT_EQ(outcome.status, kUserError) << outcome.err;
    EXPECT_TRUE(contains(outcome.err, "ggk: error: "));
    EXPECT_TRUE(contains(outcome.err, "is a directory"));
    EXPECT_TRUE(fs::is_empty(dir_ / "out"));
  }
}

TEST_F(CliTest, RunValidateAndInfo) {
  const fs::path job = write("good.toml", kBadJobHeader);
  const fs::path output = dir_ / "out" / "bad.h5";

  const Outcome validated = ggk({"validate", job.string()});
  EXPECT_EQ(validated.status, 0) << validated.err;
  EXPECT_TRUE(contains(validated.out, "ok (task maze, 2 runs x 4 sweep points)"));
  EXPECT_FALSE(fs::exists(output));

  const Outcome ran = ggk({"run", job.string(), "-j", "2"});
  ASSERT_EQ(ran.status, 0) << ran.err;
  EXPECT_TRUE(ran.out.empty()) << "results go to the HDF5 file only: " << ran.out;
  EXPECT_TRUE(contains(ran.err, "2 runs computed, 0 already complete, 8 fits"));
  EXPECT_TRUE(contains(ran.err, output.string()));
  ASSERT_TRUE(fs::exists(output));

  const Outcome info = ggk({"info", output.string()});
  EXPECT_EQ(info.status, 0) << info.err;
  EXPECT_TRUE(contains(info.out, "runs:     2 of 2 complete"));
  EXPECT_TRUE(contains(info.out, "task:     maze"));
  EXPECT_TRUE(contains(info.out, "summary:  8 fits"));

  // An existing output without --resume or --overwrite: refused, untouched.
  const std::string bytes = file_bytes(output);
  struct stat before {};
  ASSERT_EQ(::stat(output.c_str(), &before), 0);
  std::this_thread::sleep_for(20ms);  // a rewrite would show in the mtime
  for (const auto& args :
       std::vector<std::vector<std::string>>{{"run", job.string()},
                                             {"run", job.string(), "-o", output.string()},
                                             {"run", job.string(), "--resume", "--overwrite"}}) {
    const Outcome refused = ggk(args);
    EXPECT_EQ(refused.status, kUserError) << refused.err;
    EXPECT_TRUE(contains(refused.err, output.string()) ||
                contains(refused.err, "--resume and --overwrite"));
  }
  struct stat after {};
  ASSERT_EQ(::stat(output.c_str(), &after), 0);
  EXPECT_EQ(file_bytes(output), bytes);
  EXPECT_EQ(before.st_mtim.tv_sec, after.st_mtim.tv_sec);
  EXPECT_EQ(before.st_mtim.tv_nsec, after.st_mtim.tv_nsec);

  // --resume of a complete file computes nothing; --overwrite redoes it.
  const Outcome resumed = ggk({"run", job.string(), "--resume"});
  EXPECT_EQ(resumed.status, 0) << resumed.err;
  EXPECT_TRUE(contains(resumed.err, "0 runs computed, 2 already complete"));
  const Outcome overwritten = ggk({"run", job.string(), "--overwrite"});
  EXPECT_EQ(overwritten.status, 0) << overwritten.err;
  EXPECT_TRUE(contains(overwritten.err, "2 runs computed, 0 already complete"));

  // -o writes elsewhere, even when the job's own output folder is missing.
  const fs::path elsewhere = dir_ / "elsewhere.h5";
  const fs::path moved = write("moved.toml", header_with(9, "file = \"%DIR%/missing/bad.h5\""));
  const Outcome redirected = ggk({"run", moved.string(), "-q", "-o", elsewhere.string()});
  EXPECT_EQ(redirected.status, 0) << redirected.err;
  EXPECT_TRUE(fs::exists(elsewhere));
  EXPECT_TRUE(contains(ggk({"info", elsewhere.string()}).out, "runs:     2 of 2 complete"));
}

TEST_F(CliTest, InfoOnABadFileIsAUserError) {
  const fs::path missing = dir_ / "no-such.h5";
  const Outcome absent = ggk({"info", missing.string()});
  EXPECT_EQ(absent.status, kUserError);
  EXPECT_TRUE(contains(absent.err, missing.string()));

  const fs::path plain = dir_ / "plain.txt";
  const Outcome not_hdf5 = ggk({"info", plain.string()});
  EXPECT_EQ(not_hdf5.status, kUserError);
  EXPECT_TRUE(contains(not_hdf5.err, plain.string()));

  const fs::path foreign = dir_ / "foreign.h5";
  {
    Hdf5File file = Hdf5File::create(foreign);
    file.write_vector("/x", std::vector<double>{1.0});
    file.flush();
  }
  const Outcome other = ggk({"info", foreign.string()});
  EXPECT_EQ(other.status, kUserError);
  EXPECT_TRUE(contains(other.err, foreign.string()));
  EXPECT_TRUE(contains(other.err, "not a ggk results file"));
}

// Issue 37, F10: a file that a live ggk writes (its lock names a running
// process) and that reads as damaged or as no results file yet is "being
// written", exit 2, with the command to run later; not DAMAGED.
TEST_F(CliTest, VerifyOfAFileBeingWrittenSaysSo) {
  const fs::path file = dir_ / "writing.h5";
  {
    Hdf5File partial = Hdf5File::create(file);  // a ggk caught before its header
    partial.write_vector("/x", std::vector<double>{1.0});
    partial.flush();
  }
  const Outcome unlocked = ggk({"verify", file.string()});
  EXPECT_EQ(unlocked.status, kUserError);
  EXPECT_TRUE(contains(unlocked.err, "not a ggk results file")) << unlocked.err;

  char host[256] = {};
  ASSERT_EQ(gethostname(host, sizeof host - 1), 0);
  write_file(fs::path(file.string() + ".lock"),
             "ggk output lock\nhost=" + std::string(host) + "\npid=" + std::to_string(getpid()) +
                 "\nprocess_start=" + process_start(getpid()) + "\nsince=2026-11-27T16:00:00Z\n");
  const Outcome locked = ggk({"verify", file.string()});
  EXPECT_EQ(locked.status, kUserError);
  EXPECT_TRUE(contains(locked.err, "is being written by ggk pid " + std::to_string(getpid())))
      << locked.err;
  EXPECT_TRUE(contains(locked.err, "`ggk verify " + file.string() + "` again")) << locked.err;
  EXPECT_FALSE(contains(locked.out + locked.err, "DAMAGED"));
}

TEST_F(CliTest, InfoReportsAnInterruptedSweep) {
  const fs::path job = write("good.toml", kBadJobHeader);
  const fs::path output = dir_ / "out" / "bad.h5";
  ASSERT_EQ(ggk({"run", job.string(), "-q"}).status, 0);
  {
    Hdf5File file = Hdf5File::open_read_write(output);
    file.remove_attribute("/maze/run_001", "complete");
    file.remove("/maze/summary");
    file.flush();
  }
  const Outcome info = ggk({"info", output.string()});
  EXPECT_EQ(info.status, 0) << info.err;
  EXPECT_TRUE(contains(info.out, "runs:     1 of 2 complete"));
  EXPECT_TRUE(contains(info.out, "--resume"));
}

// ---------------------------------------------------------------------------
// Kill and resume.

// Starts `binary args...` with stdout and stderr going to `log`.
pid_t spawn(const fs::path& binary, const std::vector<std::string>& args, const fs::path& log) {
  std::vector<std::string> argv_strings = {binary.string()};
  argv_strings.insert(argv_strings.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& arg : argv_strings) argv.push_back(arg.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, log.c_str(),
                                   O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
  pid_t pid = -1;
  const int error = posix_spawn(&pid, binary.c_str(), &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  return error == 0 ? pid : -1;
}

std::uintmax_t size_or_zero(const fs::path& path) {
  std::error_code ec;
  const std::uintmax_t size = fs::file_size(path, ec);
  return ec ? 0 : size;
}

// 3 runs of 8 fits on the four-rooms maze, ~0.2 s per run on one core (7x that
// under the sanitizers; writing a run takes a fraction of it): time to kill the
// sweep between runs.
constexpr const char* kKillJob = R"(name = "kill"
task = "maze"
runs = 3
seed = 4242
[sweep]
basis = ["ggk", "ogk"]
kernels = [48, 64]  # ~0.6 s a run at -j 1: long enough for the kill to land between runs
sigma = [10.0]
solver = ["brm", "lstdq"]
[maze]
map_file = "%MAP%"
series = 20
steps_per_series = 150
[output]
file = "%DIR%/out/kill.h5"
)";

TEST_F(CliTest, SweepKilledMidwayIsFinishedByResume) {
  const char* source_dir = std::getenv("GGK_SOURCE_DIR");
  if (source_dir == nullptr) GTEST_SKIP() << "GGK_SOURCE_DIR is not set (run through ctest)";
  const fs::path map = fs::path(source_dir) / "jobs" / "maps" / "four-rooms.txt";
  const fs::path job_path = write("kill.toml", substitute(kKillJob, "MAP", map.string()));
  const JobSpec job = load_job_file(job_path, task_tables());
  const fs::path killed = dir_ / "out" / "kill.h5";
  const fs::path log = dir_ / "kill.log";

  // The first run's data lands in the file; once its size has stopped growing
  // for a while, the flush is done and the second run is being computed: kill
  // then. A kill that still found 0 or all runs complete is retried.
  constexpr std::uintmax_t kFirstRunBytes = 64 * 1024;
  constexpr auto kQuietPeriod = 100ms;
  std::int32_t complete_at_kill = -1;
  std::string attempts;
  for (int attempt = 0; attempt < 3; ++attempt) {
    fs::remove(killed);
    const pid_t pid = spawn(binary_, {"run", job_path.string(), "-j", "1"}, log);
    ASSERT_GT(pid, 0);
    const auto deadline = std::chrono::steady_clock::now() + 60s;
    std::uintmax_t last_size = 0;
    auto last_change = std::chrono::steady_clock::now();
    bool exited = false;
    while (std::chrono::steady_clock::now() < deadline) {
      int status = 0;
      if (::waitpid(pid, &status, WNOHANG) == pid) {
        exited = true;
        break;
      }
      const std::uintmax_t size = size_or_zero(killed);
      const auto now = std::chrono::steady_clock::now();
      if (size != last_size) {
        last_size = size;
        last_change = now;
      } else if (size >= kFirstRunBytes && now - last_change >= kQuietPeriod) {
        break;
      }
      std::this_thread::sleep_for(2ms);
    }
    if (!exited) {
      ASSERT_EQ(::kill(pid, SIGKILL), 0);
      int status = 0;
      ASSERT_EQ(::waitpid(pid, &status, 0), pid);
      if (!(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL)) exited = true;
    }
    if (exited) {
      attempts += "attempt " + std::to_string(attempt) + ": ggk finished before the kill; ";
      continue;
    }
    // A killed ggk leaves a file that opens, with whole runs marked complete.
    ASSERT_TRUE(fs::exists(killed)) << file_bytes(log);
    std::int32_t complete = 0;
    ASSERT_NO_THROW({
      const Hdf5File file = Hdf5File::open_read_only(killed);
      EXPECT_EQ(file.read_string_attribute("/", "job"), job.source_text);
      for (std::int32_t run = 0; run < job.runs; ++run) {
        if (run_is_complete(file, job.task, run)) {
          ++complete;
          // A complete run is whole.
          EXPECT_EQ(file.read_table(run_group(job.task, run) + "/fit_metrics").size(), 8u);
        }
      }
    }) << "the file of a killed sweep must open";
    attempts += "attempt " + std::to_string(attempt) + ": " + std::to_string(complete) +
                " runs complete at the kill; ";
    if (complete >= 1 && complete < job.runs) {
      complete_at_kill = complete;
      break;
    }
  }
  if (complete_at_kill < 0) {
    GTEST_SKIP() << "the kill never landed between runs (timing): " << attempts;
  }
  RecordProperty("complete_at_kill", complete_at_kill);

  const Outcome resumed = ggk({"run", job_path.string(), "--resume", "-j", "2"});
  ASSERT_EQ(resumed.status, 0) << resumed.err;
  EXPECT_TRUE(contains(resumed.err, std::to_string(job.runs - complete_at_kill) +
                                        " runs computed, " + std::to_string(complete_at_kill) +
                                        " already complete"));
  EXPECT_TRUE(contains(ggk({"info", killed.string()}).out, "runs:     3 of 3 complete"));

  const fs::path reference = dir_ / "reference.h5";
  const Outcome uninterrupted =
      ggk({"run", job_path.string(), "-j", "2", "-q", "-o", reference.string()});
  ASSERT_EQ(uninterrupted.status, 0) << uninterrupted.err;

  // Real fits, then every deterministic number of every run the same.
  {
    const Hdf5File a = Hdf5File::open_read_only(reference);
    for (const SweepPoint& point : expand_sweep(job)) {
      const std::string weights =
          run_group(job.task, 0) + "/fits/" + fit_group_name(job, point) + "/weights";
      EXPECT_FALSE(a.read_vector<double>(weights).empty()) << weights;
    }
    EXPECT_EQ(a.read_table("/maze/summary").size(), 3u * 8u);
  }
  expect_identical_results(job, reference, killed);
}

}  // namespace
}  // namespace ggk::engine
