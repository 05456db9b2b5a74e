// Room on disk before a commit (engine/store/disk_room.hpp): the room is the
// file system's free space for this user, cut to what the file size limit
// leaves the file; require_room refuses more, naming what and where.

#include "engine/store/disk_room.hpp"

#include <sys/resource.h>
#include <sys/statvfs.h>

#include <cstdint>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "support/files.hpp"
#include "support/ggk_binary.hpp"

namespace ggk::engine {
namespace {

using namespace test_support;

// Lowers the soft file size limit for the object's lifetime.
class FileSizeLimit {
 public:
  explicit FileSizeLimit(rlim_t bytes) {
    ::getrlimit(RLIMIT_FSIZE, &saved_);
    rlimit lowered = saved_;
    lowered.rlim_cur = bytes;
    ::setrlimit(RLIMIT_FSIZE, &lowered);
  }
  ~FileSizeLimit() { ::setrlimit(RLIMIT_FSIZE, &saved_); }

 private:
  rlimit saved_{};
};

TEST(DiskRoom, IsTheFreeSpaceOfTheFileSystem) {
  const ScratchDir scratch("ggk-disk-room");
  const auto file = scratch.path() / "results.h5";
  struct statvfs status {};
  ASSERT_EQ(::statvfs(scratch.path().c_str(), &status), 0);
  rlimit limit{};
  ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &limit), 0);
  if (limit.rlim_cur != RLIM_INFINITY) GTEST_SKIP() << "a file size limit is set";
  const std::uint64_t before = static_cast<std::uint64_t>(status.f_bavail) * status.f_frsize;
  const std::uint64_t room = room_for(file);
  // Other processes write too: equal to a few MB.
  EXPECT_NEAR(static_cast<double>(room), static_cast<double>(before), 64e6);
  EXPECT_NO_THROW(require_room(file, 1, "run 0"));
}

TEST(DiskRoom, TheFileSizeLimitLeavesTheLimitLessTheFile) {
  const ScratchDir scratch("ggk-disk-room");
  const auto file = write_file(scratch.path() / "results.h5", std::string(3000, 'x'));
  const FileSizeLimit limit(10000);
  EXPECT_EQ(room_for(file), 7000u);
  EXPECT_NO_THROW(require_room(file, 7000, "run 4"));
  try {
    require_room(file, 7001, "run 4");
    FAIL() << "expected the commit to be refused";
  } catch (const std::runtime_error& error) {
    const std::string message = error.what();
    EXPECT_TRUE(contains(message, "no room to write run 4 to " + file.string()));
    EXPECT_TRUE(contains(message, "0.0 MB are left")) << message;
    EXPECT_TRUE(contains(message, "nothing of it was written"));
  }
  // A file already past the limit has no room at all.
  const FileSizeLimit smaller(2000);
  EXPECT_EQ(room_for(file), 0u);
}

}  // namespace
}  // namespace ggk::engine
