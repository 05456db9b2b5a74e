// open_results (engine/run/open_results.hpp): what `ggk run` does with an
// existing output: --resume continues the same job's file (computing only the
// runs it lacks, refusing another job's or a changed input), an existing output
// needs --resume or --overwrite, and a bad output is a UsageError that leaves it
// as it was. The tests go through run_job, as the CLI does.

#include "engine/run/open_results.hpp"

#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "engine/hdf5/hdf5_file.hpp"
#include "engine/job/usage_error.hpp"
#include "engine/run/job_runner.hpp"
#include "engine/store/run_store.hpp"
#include "support/determinism_job.hpp"
#include "support/files.hpp"
#include "support/results_compare.hpp"

namespace ggk::engine {
namespace {

namespace fs = std::filesystem;
using namespace test_support;

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

// Issue 37, F8: a root `task` that is not the job's (here an 8 MB name) is
// refused, with the name cut, and the file left as it was; before, --resume
// exited 0 and `ggk info` kept advising --resume.
TEST_F(JobRunnerTest, ResumeRefusesAFileOfAnotherTaskNamingItShortly) {
  const std::string text = determinism_job(dir_ / "out.h5");
  const JobSpec job = load_job("job.toml", text);
  run_job(job, options_for(job.output.file));
  {
    Hdf5File file = Hdf5File::open_read_write(job.output.file);
    file.remove_attribute("/", "task");
    file.write_string_attribute("/", "task", std::string(8'000'000, 'x'));
    file.flush();
  }
  const std::string bytes = file_bytes(job.output.file);
  RunOptions resume = options_for(job.output.file);
  resume.resume = true;
  try {
    run_job(job, resume);
    FAIL() << "expected a UsageError";
  } catch (const UsageError& error) {
    const std::string message = error.what();
    EXPECT_LT(message.size(), 600u);
    EXPECT_NE(message.find("(8000000 bytes) results, not " + job.task + " results"),
              std::string::npos)
        << message;
  }
  EXPECT_EQ(file_bytes(job.output.file), bytes) << "a refused resume must not change the file";
}

// Issue 37, F7: a killed writer leaves bytes past the file's allocated end (its
// uncommitted staging); a refused resume left HDF5 to cut them when it closed the
// file it had opened for writing (22 of 34 refusals in the fault campaign). The
// job is now compared on a read-only handle: the refusal changes no byte.
TEST_F(JobRunnerTest, ARefusedResumeLeavesBytesPastTheAllocatedEnd) {
  const std::string text = determinism_job(dir_ / "out.h5");
  const JobSpec job = load_job("job.toml", text);
  run_job(job, options_for(job.output.file));
  {
    std::ofstream tail(job.output.file, std::ios::binary | std::ios::app);
    tail << std::string(4096, '\x5a');  // what a writer killed mid-flush leaves
  }
  std::string other_text = text;
  other_text.replace(other_text.find("seed = 20240917"), 15, "seed = 20240918");
  const JobSpec other = load_job("other.toml", other_text);
  const std::string bytes = file_bytes(job.output.file);
  RunOptions resume = options_for(job.output.file);
  resume.resume = true;
  EXPECT_THROW(run_job(other, resume), UsageError);
  EXPECT_EQ(file_bytes(job.output.file), bytes) << "a refused resume must not change the file";
}

// Issue 37, F5: a reader holding the file (another process: a notebook's h5py
// handle, a `ggk info` loop) keeps HDF5's lock; --resume failed with "unable to
// lock file, errno = 11" every time. It now waits briefly, then opens the file as
// the writer does between runs, without HDF5's lock (ggk's own lock is held).
TEST_F(JobRunnerTest, ResumeGoesOnWhileAReaderHoldsTheFile) {
  const std::string text = determinism_job(dir_ / "out.h5");
  JobSpec job = load_job("job.toml", text);
  job.runs = 2;
  run_job(job, options_for(job.output.file));
  int ready[2];
  ASSERT_EQ(pipe(ready), 0);
  const pid_t reader = fork();
  ASSERT_GE(reader, 0);
  if (reader == 0) {
    const Hdf5File held = Hdf5File::open_read_only(job.output.file);
    const char byte = 1;
    (void)!write(ready[1], &byte, 1);
    pause();  // until killed
    _exit(0);
  }
  char byte = 0;
  ASSERT_EQ(read(ready[0], &byte, 1), 1);  // the reader has the file open
  job.runs = 3;
  RunOptions resume = options_for(job.output.file);
  resume.resume = true;
  RunSummary summary;
  EXPECT_NO_THROW(summary = run_job(job, resume));
  kill(reader, SIGKILL);
  waitpid(reader, nullptr, 0);
  close(ready[0]);
  close(ready[1]);
  EXPECT_EQ(summary.runs_computed, 1);
  EXPECT_EQ(summary.runs_skipped, 2);
}

TEST_F(JobRunnerTest, ResumeComparesTheJobsMeaning) {
  // sigma = [3] and [3.0], a key at its default written out, comments and key
  // order: the same job, so the file resumes (issue 20: resumes that never mislead).
  const std::string text = determinism_job(dir_ / "out.h5");
  const JobSpec job = load_job("job.toml", text);
  run_job(job, options_for(job.output.file));

  std::string respelled = "# respelled\n" + text;
  respelled.replace(respelled.find("sigma = [3.0]"), 13, "sigma = [3]");
  respelled += "[lspi]\ngamma = 0.9\nmax_iterations = 20\n";
  RunOptions resume = options_for(job.output.file);
  resume.resume = true;
  const RunSummary summary = run_job(load_job("respelled.toml", respelled), resume);
  EXPECT_EQ(summary.runs_skipped, 3);
  EXPECT_EQ(summary.runs_computed, 0);

  // A value that changes the results is named.
  std::string changed = text;
  changed.replace(changed.find("slip = 0.2"), 10, "slip = 0.3");
  try {
    run_job(load_job("changed.toml", changed), resume);
    FAIL() << "expected a UsageError";
  } catch (const UsageError& error) {
    EXPECT_NE(
        std::string(error.what()).find("maze.slip: 0.2 in the results file, 0.3 in the job file"),
        std::string::npos)
        << error.what();
  }
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

// A results file damaged beyond its runs (cut short, or the summary's object
// header overwritten) is not resumed in place, where every try met the same
// damage: its runs that read back whole are copied into a new file, the rest
// is computed, the result equals the whole job's, and the damaged file stays
// beside it under <stem>.damaged.h5 unless every run was copied. A second resume
// then computes nothing.
TEST_F(JobRunnerTest, ResumeOfAFileDamagedBeyondItsRunsSalvagesItsRuns) {
  const JobSpec job = load_job("job.toml", determinism_job(dir_ / "unused.h5"));
  const fs::path reference = dir_ / "reference.h5";
  run_job(job, options_for(reference));
  const auto size = static_cast<std::int64_t>(fs::file_size(reference));

  struct Case {
    std::string name;
    std::int64_t cut_to;  // bytes kept; 0: the summary's header overwritten instead
  };
  for (const Case& c : {Case{"cut_10", size / 10}, Case{"cut_50", size / 2},
                        Case{"cut_90", size * 9 / 10}, Case{"summary", 0}}) {
    SCOPED_TRACE(c.name);
    const fs::path damaged = dir_ / (c.name + ".h5");
    fs::copy_file(reference, damaged);
    if (c.cut_to > 0) {
      fs::resize_file(damaged, static_cast<std::uintmax_t>(c.cut_to));
    } else {
      const std::uint64_t header =
          Hdf5File::open_read_only(damaged).hard_link_address("/maze/summary").value();
      std::fstream bytes(damaged, std::ios::in | std::ios::out | std::ios::binary);
      bytes.seekp(static_cast<std::streamoff>(header));
      const std::string garbage(16, '\xff');
      bytes.write(garbage.data(), static_cast<std::streamsize>(garbage.size()));
    }
    RunOptions resume = options_for(damaged);
    resume.resume = true;
    RunSummary summary;
    ASSERT_NO_THROW(summary = run_job(job, resume));
    EXPECT_EQ(summary.runs_computed + summary.runs_skipped, 3);
    if (c.cut_to == 0) {
      EXPECT_EQ(summary.runs_skipped, 3);  // every run was whole
    }
    expect_identical_results(job, reference, damaged);
    // Kept aside where a run was lost with it; where every run was copied whole
    // a copy would keep nothing (F6: a full-size copy was left behind).
    EXPECT_EQ(fs::exists(dir_ / (c.name + ".damaged.h5")), summary.runs_skipped < 3);
    EXPECT_FALSE(fs::exists(dir_ / (c.name + ".h5.part")));

    const RunSummary again = run_job(job, resume);
    EXPECT_EQ(again.runs_computed, 0);
    EXPECT_EQ(again.runs_skipped, 3);
    EXPECT_FALSE(fs::exists(dir_ / (c.name + ".damaged-2.h5")));
  }
}

}  // namespace
}  // namespace ggk::engine
