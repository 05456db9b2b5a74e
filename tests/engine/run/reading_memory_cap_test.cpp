// The room a reader of an untrusted file allows itself (reading_memory_cap.hpp)
// and what a failed allocation then means (hdf5/allocation_failures.hpp).

#include "engine/run/reading_memory_cap.hpp"

#include <gtest/gtest.h>
#include <sys/resource.h>
#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>

#include "engine/hdf5/allocation_failures.hpp"
#include "engine/hdf5/hdf5_file.hpp"
#include "engine/run/isolated_reading.hpp"

namespace ggk::engine {
namespace {

namespace fs = std::filesystem;

fs::path scratch_file(const std::string& name) {
  return fs::temp_directory_path() / ("ggk-reading-cap-" + std::to_string(::getpid()) + "-" + name);
}

std::uint64_t soft_limit() {
  rlimit limit{};
  EXPECT_EQ(::getrlimit(RLIMIT_AS, &limit), 0);
  return limit.rlim_cur;
}

TEST(ReadingMemoryCap, TheRoomIsTheAddressSpaceInUsePlusAGigabytePlus16TimesTheFiles) {
  const fs::path file = scratch_file("sized");
  std::ofstream(file) << std::string(1000000, 'x');
  const ReadingRoom one = ReadingRoom::for_files({file});
  const ReadingRoom two = ReadingRoom::for_files({file, file});
  EXPECT_GE(one.bytes, (std::uint64_t{1} << 30) + 16000000);
  // The second file adds 16 x its size (the address space in use moved little between).
  EXPECT_NEAR(static_cast<double>(two.bytes - one.bytes), 16e6, 4e6);
  fs::remove(file);
}

TEST(ReadingMemoryCap, WhileItLivesAllocationsBeyondTheRoomFailAndMeanDamage) {
  if (!ReadingMemoryCap::available()) GTEST_SKIP() << "not set under AddressSanitizer";
  if (soft_limit() != RLIM_INFINITY) GTEST_SKIP() << "this test runs under ulimit -v";
  const ReadingRoom room = ReadingRoom::for_files({});
  ASSERT_FALSE(room.user_limit_binds);
  {
    const ReadingMemoryCap cap(room);
    EXPECT_EQ(soft_limit(), room.bytes);
    EXPECT_EQ(allocation_failures(), AllocationFailure::kDamage);
    void* beyond = std::malloc(static_cast<std::size_t>(room.bytes));  // more than is left
    EXPECT_EQ(beyond, nullptr);
    std::free(beyond);
  }
  EXPECT_EQ(soft_limit(), RLIM_INFINITY);
  EXPECT_EQ(allocation_failures(), AllocationFailure::kOutOfMemory);
}

// Under the user's tighter limit the cap sets nothing: a failed allocation is
// that limit running out (not damage), and the messages say so.
TEST(ReadingMemoryCap, UnderATighterUserLimitFailuresMeanOutOfMemory) {
  if (soft_limit() != RLIM_INFINITY) GTEST_SKIP() << "this test runs under ulimit -v";
  const ReadingRoom unbounded = ReadingRoom::for_files({});
  rlimit limit{};
  ASSERT_EQ(::getrlimit(RLIMIT_AS, &limit), 0);
  rlimit tight = limit;
  tight.rlim_cur = unbounded.bytes - (std::uint64_t{512} << 20);
  ASSERT_EQ(::setrlimit(RLIMIT_AS, &tight), 0);
  const ReadingRoom room = ReadingRoom::for_files({});
  {
    const ReadingMemoryCap cap(room);
    EXPECT_EQ(soft_limit(), tight.rlim_cur);
    EXPECT_EQ(allocation_failures(), AllocationFailure::kOutOfMemory);
  }
  ASSERT_EQ(::setrlimit(RLIMIT_AS, &limit), 0);
  EXPECT_TRUE(room.user_limit_binds);
  EXPECT_NE(room.limit_words("a.h5").find("(ulimit -v), less than the"), std::string::npos)
      << room.limit_words("a.h5");
}

// A file with one string attribute whose stored length is set to ~4 GB, as a
// fuzzed byte did (stop 41's campaign, F1): HDF5 allocates that length before it
// finds the damage. Returns the file.
fs::path file_with_a_damaged_string_length() {
  const fs::path file = scratch_file("damaged.h5");
  {
    Hdf5File h5 = Hdf5File::create(file);
    h5.create_group("/run");
    h5.write_string_attribute("/run", "units", "metres per second");
    h5.close();
  }
  std::ifstream in(file, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  in.close();
  // The attribute's value on disk: its length (uint32), then the address of its
  // global heap collection ("GCOL") and the object's index.
  const std::size_t heap = bytes.find("GCOL");
  EXPECT_NE(heap, std::string::npos);
  std::string stored(12, '\0');
  const std::uint32_t length = 17;  // "metres per second"
  for (int i = 0; i < 4; ++i) stored[i] = static_cast<char>((length >> (8 * i)) & 0xff);
  for (int i = 0; i < 8; ++i) stored[4 + i] = static_cast<char>((heap >> (8 * i)) & 0xff);
  const std::size_t at = bytes.find(stored);
  EXPECT_NE(at, std::string::npos) << "the value's length was not found";
  bytes[at + 3] = static_cast<char>(0xf0);  // 17 -> 4026531857 bytes
  std::ofstream(file, std::ios::binary | std::ios::trunc) << bytes;
  return file;
}

TEST(ReadingMemoryCap, ADamagedStringLengthIsDamageNotAnAllocationOfGigabytes) {
  if (!ReadingMemoryCap::available()) GTEST_SKIP() << "not set under AddressSanitizer";
  if (soft_limit() != RLIM_INFINITY) GTEST_SKIP() << "this test runs under ulimit -v";
  const fs::path file = file_with_a_damaged_string_length();
  // read_isolated reads in a child under the cap; the child says what it found.
  const int status = read_isolated({file}, [&] {
    const Hdf5File h5 = Hdf5File::open_read_only(file);
    try {
      (void)h5.read_attribute_values("/run", "units");
    } catch (const std::runtime_error& e) {
      return std::string(e.what()).find("within the room ggk allows") != std::string::npos ? 3 : 4;
    }
    return 5;  // read it: the damage was not where the test put it
  });
  EXPECT_EQ(status, 3) << "4: another error; 5: read whole";
  fs::remove(file);
}

}  // namespace
}  // namespace ggk::engine
