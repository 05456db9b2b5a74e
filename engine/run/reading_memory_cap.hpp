#pragma once
// The address space a reader of files it does not trust allows itself
// (hdf5/allocation_failures.hpp says why: a damaged length makes HDF5 allocate
// it before it can check; fuzzed 3 MB files asked for 4.1 GB per string, and
// for 10-22 GB in all, which the OOM killer answered).
//
// Reading a whole results file needs far less than the file's size in address
// space beyond what the process holds (measured: `ggk verify` of the 151 MB
// khepera-paper file peaks at 2.8x its size in RSS; the largest ratio of a
// dataset's values to its compressed bytes in the shipped results is 435:1, on
// datasets of a few kB). The room allowed: the address space in use plus
// 1 GiB plus 16 x the files' bytes. Where the process's own RLIMIT_AS (ulimit -v)
// is lower, that limit binds instead: then a failed allocation is the user's
// limit running out, not damage.
//
// A ReadingMemoryCap sets the soft RLIMIT_AS to the room and the meaning of a
// failed allocation (allocation_failures.hpp) while it lives, and restores both.
// Not under AddressSanitizer (which ends the process when an mmap fails).
// Only while one thread allocates: a reading child (isolated_reading.hpp), or
// `run` reading its output back before any computing thread exists.

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace ggk::engine {

// The room for reading `files`, and whose limit binds. Computed, not applied.
struct ReadingRoom {
  std::uint64_t bytes = 0;        // the soft RLIMIT_AS to set: in use + 1 GiB + 16 x files
  std::uint64_t user_limit = 0;   // the process's soft RLIMIT_AS; 0 when unlimited
  bool user_limit_binds = false;  // user_limit <= bytes: failures are out-of-memory

  static ReadingRoom for_files(const std::vector<std::filesystem::path>& files);

  // "the address-space limit of 120 MB (ulimit -v), less than the 1.1 GB ggk
  // allows itself for reading A" (for a message; empty unless user_limit_binds).
  std::string limit_words(const std::string& names) const;
};

class ReadingMemoryCap {
 public:
  explicit ReadingMemoryCap(const ReadingRoom& room);
  static bool available();  // false under AddressSanitizer
  ~ReadingMemoryCap();
  ReadingMemoryCap(const ReadingMemoryCap&) = delete;
  ReadingMemoryCap& operator=(const ReadingMemoryCap&) = delete;

 private:
  std::uint64_t previous_soft_ = 0;
  bool lowered_ = false;
};

}  // namespace ggk::engine
