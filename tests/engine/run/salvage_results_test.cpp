// The parts of salvaging a results file (engine/run/salvage_results.hpp): which
// errors are the machine's, where the damaged file is kept, and which runs are
// copied. The whole salvage through --resume: open_results_test.cpp
// (ResumeOfAFileDamagedBeyondItsRunsSalvagesItsRuns).

#include "engine/run/salvage_results.hpp"

#include <sys/stat.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "engine/job/usage_error.hpp"
#include "engine/store/run_store.hpp"
#include "support/determinism_job.hpp"
#include "support/files.hpp"

namespace ggk::engine {
namespace {

namespace fs = std::filesystem;
using namespace test_support;

TEST(SalvageResults, TheMachinesErrorsAreReportedNotSalvaged) {
  for (const char* message :
       {"HDF5 file 'x.h5': cannot flush '/': file write failed: No space left on device",
        "file write failed: File too large", "no room to write run 3 to x.h5: ...",
        "unable to open file: Permission denied", "Read-only file system", "Disk quota exceeded"}) {
    EXPECT_TRUE(machine_error(message)) << message;
  }
  for (const char* message :
       {"cannot move '/maze/summary' to '/.staging/maze/summary_old': bad object header version",
        "can't find section node on size list", "len not positive after adjustment for EOA",
        "link iteration failed: bad symbol table node signature"}) {
    EXPECT_FALSE(machine_error(message)) << message;
  }
}

TEST_F(JobRunnerTest, TheDamagedFileIsKeptUnderTheFirstFreeName) {
  const fs::path output = dir_ / "out.h5";
  std::ofstream(output) << "results";
  const fs::path first = keep_damaged_aside(output);
  EXPECT_EQ(first, dir_ / "out.damaged.h5");
  const fs::path second = keep_damaged_aside(output);
  EXPECT_EQ(second, dir_ / "out.damaged-2.h5");
  struct stat a {
  }, b{};
  ASSERT_EQ(::stat(output.c_str(), &a), 0);
  ASSERT_EQ(::stat(second.c_str(), &b), 0);
  EXPECT_EQ(a.st_ino, b.st_ino);  // a link: no copy, no room needed
  EXPECT_EQ(a.st_nlink, 3u);
}

TEST_F(JobRunnerTest, OnlyCompleteRunsThatReadBackWholeAreCopied) {
  const JobSpec job = load_job("job.toml", determinism_job(dir_ / "out.h5"));
  run_job(job, options_for(job.output.file));
  {
    Hdf5File file = Hdf5File::open_read_write(job.output.file);
    file.remove_attribute("/maze/run_001", "complete");  // cut by a kill
    file.remove("/maze/run_002/fits");                   // not whole
    file.flush();
  }
  const Hdf5File damaged = Hdf5File::open_read_only(job.output.file);
  Hdf5File fresh = Hdf5File::create(dir_ / "fresh.h5", Hdf5File::CreateMode::kFailIfExists);
  SalvageCount count;
  const auto copied = copy_readable_runs(damaged, fresh, study_of(job), count);
  ASSERT_EQ(copied.size(), 1u);
  EXPECT_EQ(copied[0], std::vector<std::int32_t>{0});
  EXPECT_EQ(count.copied, 1);
  EXPECT_EQ(count.unreadable, 1);  // run 2; run 1 was never complete
  EXPECT_EQ(count.lost_lists, 0);
  EXPECT_TRUE(run_is_complete(fresh, "maze", 0));
  EXPECT_FALSE(fresh.exists("/maze/run_001"));
  EXPECT_FALSE(fresh.exists("/maze/run_002"));
}

}  // namespace
}  // namespace ggk::engine
