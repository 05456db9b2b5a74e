// ggk's own lock on a results file: exclusive, named holder, stale locks of dead
// processes taken over, never another's lock removed.

#include "engine/store/output_lock.hpp"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fstream>
#include <iterator>
#include <string>

#include "engine/job/usage_error.hpp"

namespace ggk::engine {
namespace {

namespace fs = std::filesystem;

std::string host() {
  char name[256] = {};
  ::gethostname(name, sizeof name - 1);
  return name;
}

std::string text_of(const fs::path& path) {
  std::ifstream in(path);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

class OutputLockTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           ("ggk_output_lock_test_" + std::to_string(::getpid()) + "_" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path results() const { return dir_ / "r.h5"; }
  fs::path lock() const { return OutputLock::path_for(results()); }
  void write_lock(const std::string& text) const { std::ofstream(lock()) << text; }

  fs::path dir_;
};

TEST_F(OutputLockTest, SecondHolderIsRefusedWithTheHolderNamed) {
  OutputLock first = OutputLock::acquire(results());
  EXPECT_TRUE(first.held());
  EXPECT_NE(text_of(lock()).find("pid=" + std::to_string(::getpid())), std::string::npos);
  try {
    (void)OutputLock::acquire(results());
    FAIL() << "a second lock was granted";
  } catch (const UsageError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("pid " + std::to_string(::getpid()) + " on host " + host()),
              std::string::npos)
        << message;
  }
  first.release();
  EXPECT_FALSE(fs::exists(lock()));
  EXPECT_TRUE(OutputLock::acquire(results()).held());
  EXPECT_FALSE(fs::exists(lock())) << "released when the holder goes";
}

TEST_F(OutputLockTest, StaleLockOfADeadProcessOnThisHostIsTakenOver) {
  const pid_t child = ::fork();
  if (child == 0) ::_exit(0);
  ASSERT_GT(child, 0);
  ::waitpid(child, nullptr, 0);  // a pid that no longer runs
  write_lock("ggk output lock\nhost=" + host() + "\npid=" + std::to_string(child) +
             "\nprocess_start=1\nsince=earlier\n");
  const OutputLock taken = OutputLock::acquire(results());
  EXPECT_NE(text_of(lock()).find("pid=" + std::to_string(::getpid())), std::string::npos);
}

TEST_F(OutputLockTest, LockOfAnExitedProcessNotYetReapedIsStale) {
  // A zombie: exited, not waited for (an MPI rank whose mpirun returned first).
  const pid_t child = ::fork();
  if (child == 0) ::_exit(0);
  ASSERT_GT(child, 0);
  for (int i = 0; i < 200 && ::kill(child, 0) == 0; ++i) {
    std::ifstream stat("/proc/" + std::to_string(child) + "/stat");
    std::string text{std::istreambuf_iterator<char>(stat), std::istreambuf_iterator<char>()};
    if (text.find(") Z") != std::string::npos) break;
    ::usleep(10000);
  }
  write_lock("ggk output lock\nhost=" + host() + "\npid=" + std::to_string(child) +
             "\nprocess_start=\nsince=earlier\n");
  EXPECT_TRUE(OutputLock::acquire(results()).held());
  ::waitpid(child, nullptr, 0);
}

TEST_F(OutputLockTest, LockOfALiveProcessWithAnotherStartTimeIsStale) {
  // Our own pid, but a start time that is not ours: a reused pid.
  write_lock("ggk output lock\nhost=" + host() + "\npid=" + std::to_string(::getpid()) +
             "\nprocess_start=1\nsince=earlier\n");
  EXPECT_TRUE(OutputLock::acquire(results()).held());
}

TEST_F(OutputLockTest, LockFromAnotherHostIsRefusedAndKept) {
  const std::string foreign =
      "ggk output lock\nhost=node-that-is-not-here\npid=1\nprocess_start=1\nsince=earlier\n";
  write_lock(foreign);
  try {
    (void)OutputLock::acquire(results());
    FAIL() << "another host's lock was taken";
  } catch (const UsageError& e) {
    EXPECT_NE(std::string(e.what()).find("on host node-that-is-not-here"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("remove " + lock().string()), std::string::npos);
  }
  EXPECT_EQ(text_of(lock()), foreign);
}

// Something at the lock's path that no ggk wrote is named for what it is,
// exit status 2, and left alone (before: "internal error: basic_filebuf::
// underflow" for a directory, "other ggk processes keep taking it" for a
// dangling symbolic link).
TEST_F(OutputLockTest, ALockPathThatIsNoFileIsNamed) {
  const auto refusal = [&] {
    try {
      (void)OutputLock::acquire(results());
    } catch (const UsageError& e) {
      return std::string(e.what());
    }
    return std::string("(taken)");
  };
  fs::create_directory(lock());
  EXPECT_NE(refusal().find(lock().string() + " is a directory, not a ggk lock file"),
            std::string::npos)
      << refusal();
  EXPECT_TRUE(fs::is_directory(lock()));
  fs::remove(lock());
  fs::create_symlink(dir_ / "nowhere", lock());
  EXPECT_NE(refusal().find(" is a symbolic link to nothing"), std::string::npos) << refusal();
  EXPECT_TRUE(fs::is_symlink(lock()));
}

TEST_F(OutputLockTest, ReleaseNeverRemovesAnotherHoldersLock) {
  OutputLock mine = OutputLock::acquire(results());
  const std::string other =
      "ggk output lock\nhost=elsewhere\npid=2\nprocess_start=1\nsince=later\n";
  write_lock(other);  // someone removed ours and took it (by hand)
  mine.release();
  EXPECT_EQ(text_of(lock()), other);
}

TEST_F(OutputLockTest, UnwritableDirectoryIsAUserError) {
  if (::geteuid() == 0) GTEST_SKIP() << "root writes anywhere";
  fs::permissions(dir_, fs::perms::owner_read | fs::perms::owner_exec);
  EXPECT_THROW((void)OutputLock::acquire(results()), UsageError);
  fs::permissions(dir_, fs::perms::owner_all);
}

}  // namespace
}  // namespace ggk::engine
