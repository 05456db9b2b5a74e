// Files a job names, and the job file itself, as a hostile user would give them:
// FIFOs, devices, symlink loops, files far too large. Each must be refused at
// once with one JobError naming the file and key, never waited on or read until
// memory runs out.

#include "engine/job/job_input.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <future>
#include <memory>
#include <string>
#include <thread>

#include <gtest/gtest.h>

#include "engine/job/job_file.hpp"
#include "engine/tasks/task_list.hpp"

namespace ggk::engine {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

constexpr const char* kMapFileText =
    "#######\n"
    "#.....#\n"
    "#.###.#\n"
    "#....G#\n"
    "#######\n";

// A job whose map_file is `map_file`.
std::string job_with_map_file(const std::string& map_file) {
  return "name = \"hostile\"\ntask = \"maze\"\nruns = 1\nseed = 0\n"
         "[sweep]\nkernels = [4]\nsigma = [2.0]\n"
         "[maze]\nmap_file = \"" +
         map_file + "\"\n";
}

// Loads `path` on a thread of its own and gives its JobError message, "loaded",
// "other exception: ..." or "timed out" after 10 s. On a timeout the thread is
// left behind, blocked: a regression must fail the test, not hang the suite.
std::string load_outcome(const fs::path& path) {
  auto outcome = std::make_shared<std::promise<std::string>>();
  std::future<std::string> result = outcome->get_future();
  std::thread([outcome, path] {
    try {
      JobLoadOptions options;
      options.check_output = false;
      load_job_file(path, task_tables(), options);
      outcome->set_value("loaded");
    } catch (const JobError& error) {
      outcome->set_value(error.what());
    } catch (const std::exception& error) {
      outcome->set_value(std::string("other exception: ") + error.what());
    }
  }).detach();
  if (result.wait_for(10s) != std::future_status::ready) return "timed out";
  return result.get();
}

class JobInputTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string pattern = (fs::temp_directory_path() / "ggk-job-input-XXXXXX").string();
    ASSERT_NE(::mkdtemp(pattern.data()), nullptr);
    dir_ = pattern;
    write("small.txt", kMapFileText);
  }
  void TearDown() override {
    std::error_code ignored;
    fs::remove_all(dir_, ignored);
  }
  fs::path write(const std::string& name, const std::string& text) const {
    const fs::path path = dir_ / name;
    std::ofstream(path, std::ios::binary) << text;
    return path;
  }
  fs::path make_fifo(const std::string& name) const {
    const fs::path path = dir_ / name;
    EXPECT_EQ(::mkfifo(path.c_str(), 0600), 0);
    return path;
  }
  // a -> b -> a
  fs::path make_symlink_loop(const std::string& a, const std::string& b) const {
    fs::create_symlink(b, dir_ / a);
    fs::create_symlink(a, dir_ / b);
    return dir_ / a;
  }
  // A file of `bytes` bytes that takes no space (truncate(2) on an empty file).
  fs::path make_sparse(const std::string& name, std::int64_t bytes) const {
    const fs::path path = write(name, "");
    EXPECT_EQ(::truncate(path.c_str(), static_cast<off_t>(bytes)), 0);
    return path;
  }
  std::string map_file_outcome(const std::string& map_file) const {
    return load_outcome(write("job.toml", job_with_map_file(map_file)));
  }

  fs::path dir_;
};

void expect_contains(const std::string& text, const std::string& part) {
  EXPECT_NE(text.find(part), std::string::npos) << "expected \"" << part << "\" in:\n" << text;
}

TEST_F(JobInputTest, ARegularMapFileAndASymlinkToOneAreRead) {
  EXPECT_EQ(map_file_outcome("small.txt"), "loaded");
  fs::create_symlink("small.txt", dir_ / "link.txt");
  EXPECT_EQ(map_file_outcome("link.txt"), "loaded");
}

// A job copied out of the project (issue 36: its relative map and arena paths
// broke) finds the files the project ships in its jobs/ folder; a name missing in
// both places names both; a file beside the job comes first.
TEST_F(JobInputTest, AJobCopiedElsewhereFindsTheProjectsMaps) {
  ASSERT_FALSE(project_jobs_dir().empty());
  ASSERT_TRUE(fs::exists(project_jobs_dir() / "maps" / "four-rooms.txt"));
  EXPECT_EQ(map_file_outcome("maps/four-rooms.txt"), "loaded");
  const std::string missing = map_file_outcome("maps/no-such-map.txt");
  expect_contains(missing, "does not exist, nor is ");
  expect_contains(missing, "maps/no-such-map.txt in the project's jobs/ folder");
  // Beside the job first: a map of its own under the same name wins.
  fs::create_directories(dir_ / "maps");
  write("maps/four-rooms.txt", kMapFileText);
  JobLoadOptions options;
  options.check_output = false;
  const JobSpec job = load_job_file(write("job.toml", job_with_map_file("maps/four-rooms.txt")),
                                    task_tables(), options);
  ASSERT_EQ(job.inputs.size(), 1u);
  EXPECT_EQ(job.inputs[0].text, kMapFileText);
}

TEST_F(JobInputTest, AFifoAsMapFileIsRefusedWithoutBlocking) {
  make_fifo("fifo.txt");
  const std::string message = map_file_outcome("fifo.txt");
  expect_contains(message, "job.toml:9:1: [maze] map_file: map file 'fifo.txt'");
  expect_contains(message, "is a FIFO (named pipe), not a regular file");
}

TEST_F(JobInputTest, AFifoAsJobFileIsRefusedWithoutBlocking) {
  const std::string message = load_outcome(make_fifo("job.toml"));
  expect_contains(message, "job.toml: cannot read the job file: it is a FIFO (named pipe)");
}

TEST_F(JobInputTest, AFifoAsArenaFileIsRefusedWithoutBlocking) {
  make_fifo("arena.toml");
  const std::string message = load_outcome(
      write("khepera.toml",
            "name = \"k\"\ntask = \"khepera\"\nruns = 1\nseed = 0\n"
            "[sweep]\nkernels = [4]\nsigma = [1000.0]\n"
            "[khepera]\nseries = 4\nsteps_per_series = 20\narena_file = \"arena.toml\"\n"
            "[khepera.som]\ngrid_from_samples = true\n"));
  expect_contains(message, "khepera.toml:11:1: [khepera] arena_file: arena file 'arena.toml'");
  expect_contains(message, "is a FIFO (named pipe), not a regular file");
}

TEST_F(JobInputTest, ADeviceAsMapFileIsRefusedNotReadUntilMemoryRunsOut) {
  const std::string message = map_file_outcome("/dev/zero");
  expect_contains(message, "[maze] map_file: map file '/dev/zero'");
  expect_contains(message, "is a character device, not a regular file");
}

TEST_F(JobInputTest, ASymlinkLoopIsReportedAsALoop) {
  make_symlink_loop("loop-a.txt", "loop-b.txt");
  const std::string map_message = map_file_outcome("loop-a.txt");
  expect_contains(map_message, "[maze] map_file: map file 'loop-a.txt'");
  expect_contains(map_message, "is a symbolic link loop");
  const std::string job_message = load_outcome(make_symlink_loop("job-a.toml", "job-b.toml"));
  expect_contains(job_message, "job-a.toml: cannot read the job file: it is a symbolic link loop");
}

TEST_F(JobInputTest, ADanglingSymlinkSaysSo) {
  fs::create_symlink("nowhere.txt", dir_ / "dangling.txt");
  expect_contains(map_file_outcome("dangling.txt"),
                  "map file 'dangling.txt' (" + (dir_ / "dangling.txt").string() +
                      ") is a symbolic link to a file that does not exist");
}

TEST_F(JobInputTest, FilesBeyondTheSizeLimitAreRefusedUnread) {
  make_sparse("huge.txt", kMaxInputFileBytes + 1);
  const std::string map_message = map_file_outcome("huge.txt");
  expect_contains(map_message, "[maze] map_file: map file 'huge.txt'");
  expect_contains(map_message, "is 16777217 bytes, more than the limit of 16 MiB");
  const std::string job_message = load_outcome(make_sparse("huge.toml", kMaxInputFileBytes + 1));
  expect_contains(job_message, "huge.toml: cannot read the job file: it is 16777217 bytes");
  expect_contains(job_message, "the limit of 16 MiB");
}

TEST_F(JobInputTest, ReadRegularFileReadsUpToTheLimit) {
  const fs::path path = write("text.txt", "0123456789");
  const RegularFileText whole = read_regular_file(path, 10);
  EXPECT_EQ(whole.problem, "");
  EXPECT_EQ(whole.text, "0123456789");
  const RegularFileText over = read_regular_file(path, 9);
  EXPECT_EQ(over.text, "");
  EXPECT_EQ(over.problem,
            "is 10 bytes, more than the limit of 9 bytes for a job file or a file it names");
  EXPECT_EQ(read_regular_file(dir_ / "missing.txt").problem, "does not exist");
  EXPECT_EQ(read_regular_file(dir_).problem, "is a directory");
  EXPECT_EQ(read_regular_file(dir_ / "small.txt" / "x").problem,
            "does not exist (a component of its path is not a directory)");
  EXPECT_EQ(read_regular_file(write("empty.txt", "")).problem, "");
}

}  // namespace
}  // namespace ggk::engine
