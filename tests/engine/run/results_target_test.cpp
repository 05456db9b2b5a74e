// The output of `ggk run` (engine/run/results_target.hpp): what may be at the
// output path, its directory, and the target that writes a new file under
// "<output>.part" and renames it into place with its first run.

#include "engine/run/results_target.hpp"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <utility>

#include "engine/job/usage_error.hpp"
#include "support/files.hpp"

namespace ggk::engine {
namespace {

namespace fs = std::filesystem;

TEST(ResultsTarget, OutputStateTellsAbsentEmptyAndFileAndRefusesTheRest) {
  const test_support::ScratchDir dir("ggk_results_target");
  const fs::path output = dir.path() / "r.h5";
  EXPECT_EQ(output_state(output), OutputState::kAbsent);
  std::ofstream(output).close();
  EXPECT_EQ(output_state(output), OutputState::kEmpty);
  std::ofstream(output) << "bytes";
  EXPECT_EQ(output_state(output), OutputState::kFile);
  EXPECT_THROW(output_state(dir.path()), UsageError);  // a directory
  const fs::path fifo = dir.path() / "fifo";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  try {
    output_state(fifo);
    FAIL() << "a FIFO was taken for a results file";
  } catch (const UsageError& e) {
    EXPECT_NE(std::string(e.what()).find("not a regular file"), std::string::npos) << e.what();
  }
}

TEST(ResultsTarget, TheOutputsDirectoryMustExist) {
  const test_support::ScratchDir dir("ggk_results_target");
  EXPECT_NO_THROW(check_output_directory(dir.path() / "r.h5"));
  try {
    check_output_directory(dir.path() / "missing" / "r.h5");
    FAIL() << "a missing directory was accepted";
  } catch (const UsageError& e) {
    EXPECT_NE(std::string(e.what()).find("does not exist"), std::string::npos) << e.what();
  }
}

TEST(ResultsTarget, PublishRenamesThePartFileAndAnUnpublishedOneIsRemoved) {
  const test_support::ScratchDir dir("ggk_results_target");
  const fs::path output = dir.path() / "r.h5";
  const fs::path part = temporary_results_path(output);
  EXPECT_EQ(part, dir.path() / "r.h5.part");
  {
    ResultsTarget target(output, part, OutputLock::acquire(output));
    EXPECT_EQ(target.writing_to(), part);
    Hdf5File file = Hdf5File::create(part);
    file.flush();
    target.publish(file);
    EXPECT_TRUE(target.temporary().empty());
    EXPECT_EQ(target.writing_to(), output);
    EXPECT_EQ(file.path(), output);
    EXPECT_TRUE(fs::exists(output));
    EXPECT_FALSE(fs::exists(part));
    EXPECT_TRUE(fs::exists(target.lock_file()));
  }
  EXPECT_TRUE(fs::exists(output)) << "a published file stays";
  EXPECT_FALSE(fs::exists(OutputLock::path_for(output))) << "the lock goes with the target";

  const fs::path other = dir.path() / "s.h5";
  {
    ResultsTarget target(other, temporary_results_path(other), OutputLock::acquire(other));
    std::ofstream(temporary_results_path(other)) << "half a file";
    ResultsTarget moved(std::move(target));  // the moved-from target removes nothing
    EXPECT_TRUE(fs::exists(temporary_results_path(other)));
  }
  EXPECT_FALSE(fs::exists(temporary_results_path(other))) << "an unpublished .part is removed";
  EXPECT_FALSE(fs::exists(other));
}

}  // namespace
}  // namespace ggk::engine
