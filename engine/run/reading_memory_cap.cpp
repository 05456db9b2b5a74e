#include "engine/run/reading_memory_cap.hpp"

#include <sys/resource.h>

#include <system_error>

#include "engine/hdf5/allocation_failures.hpp"
#include "engine/run/address_space.hpp"
#include "engine/tasks/run_memory.hpp"

namespace ggk::engine {

namespace {

constexpr std::uint64_t kBaseAllowance = std::uint64_t{1} << 30;  // 1 GiB
constexpr std::uint64_t kPerFileByte = 16;

// AddressSanitizer reserves terabytes of shadow and heap and ends the process
// when an mmap fails: under it the cap is not set (failures mean out of memory).
#if defined(__SANITIZE_ADDRESS__)
constexpr bool kUnderAddressSanitizer = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
constexpr bool kUnderAddressSanitizer = true;
#else
constexpr bool kUnderAddressSanitizer = false;
#endif
#else
constexpr bool kUnderAddressSanitizer = false;
#endif

}  // namespace

ReadingRoom ReadingRoom::for_files(const std::vector<std::filesystem::path>& files) {
  std::uint64_t file_bytes = 0;
  for (const std::filesystem::path& file : files) {
    std::error_code error;
    const std::uintmax_t size = std::filesystem::file_size(file, error);
    if (!error) file_bytes += size;
  }
  ReadingRoom room;
  room.bytes = static_cast<std::uint64_t>(address_space_in_use()) + kBaseAllowance +
               kPerFileByte * file_bytes;
  rlimit limit{};
  if (::getrlimit(RLIMIT_AS, &limit) == 0 && limit.rlim_cur != RLIM_INFINITY) {
    room.user_limit = limit.rlim_cur;
    room.user_limit_binds = room.user_limit <= room.bytes;
  }
  return room;
}

std::string ReadingRoom::limit_words(const std::string& names) const {
  if (!user_limit_binds) return "";
  return "the address-space limit of " + format_bytes(static_cast<double>(user_limit)) +
         " (ulimit -v), less than the " + format_bytes(static_cast<double>(bytes)) +
         " ggk allows itself for reading " + names;
}

ReadingMemoryCap::ReadingMemoryCap(const ReadingRoom& room) {
  rlimit limit{};
  if (room.user_limit_binds || room.bytes == 0 || kUnderAddressSanitizer ||
      ::getrlimit(RLIMIT_AS, &limit) != 0) {
    set_allocation_failures(AllocationFailure::kOutOfMemory);
    return;
  }
  previous_soft_ = limit.rlim_cur;
  limit.rlim_cur = room.bytes;
  if (limit.rlim_max != RLIM_INFINITY && limit.rlim_cur > limit.rlim_max) {
    limit.rlim_cur = limit.rlim_max;
  }
  lowered_ = ::setrlimit(RLIMIT_AS, &limit) == 0;
  set_allocation_failures(lowered_ ? AllocationFailure::kDamage : AllocationFailure::kOutOfMemory);
}

bool ReadingMemoryCap::available() {
  return !kUnderAddressSanitizer;
}

ReadingMemoryCap::~ReadingMemoryCap() {
  set_allocation_failures(AllocationFailure::kOutOfMemory);
  if (!lowered_) return;
  rlimit limit{};
  if (::getrlimit(RLIMIT_AS, &limit) != 0) return;
  limit.rlim_cur = previous_soft_;
  ::setrlimit(RLIMIT_AS, &limit);
}

}  // namespace ggk::engine
