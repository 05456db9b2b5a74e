#pragma once
// ggk's own lock on a results file, independent of HDF5's file locking (which
// cluster users switch off with HDF5_USE_FILE_LOCKING=FALSE on NFS and Lustre,
// where flock() is missing or unreliable).
//
// The lock is a file beside the results, "<results>.lock", holding who took it:
//   ggk output lock
//   host=<hostname>
//   pid=<pid>
//   process_start=<the holder's start time in clock ticks since boot, /proc>
//   since=<UTC time>
// It is taken with link(2), the one create-if-absent that is atomic on NFS too:
// the text is written to a private file first and hard-linked to the lock name,
// so a lock file is never seen half written. A holder that died without removing
// its lock (kill -9, a crash, a lost node) leaves it behind; on the same host the
// lock is then stale (no process with that pid and start time) and is taken
// over. A lock from another host cannot be checked from here: the message names
// the host and pid and says to remove the lock file if no ggk runs there.

#include <filesystem>
#include <optional>
#include <string>

namespace ggk::engine {

class OutputLock {
 public:
  // Takes the lock of `results` (which need not exist yet), or throws
  // UsageError naming the holder; throws UsageError when the lock file cannot
  // be written (a read-only directory, say).
  static OutputLock acquire(const std::filesystem::path& results);

  // The lock file of `results`: "<results>.lock".
  static std::filesystem::path path_for(const std::filesystem::path& results);
  // Who writes `results` now ("ggk pid 123 on host h, since 2026-11-27T16:00:00Z"),
  // when its lock names a holder that is not known to be gone; nullopt otherwise.
  static std::optional<std::string> writer_of(const std::filesystem::path& results);

  OutputLock() = default;  // holds nothing
  OutputLock(OutputLock&& other) noexcept;
  OutputLock& operator=(OutputLock&& other) noexcept;
  OutputLock(const OutputLock&) = delete;
  OutputLock& operator=(const OutputLock&) = delete;
  ~OutputLock();  // release()

  bool held() const { return !path_.empty(); }
  // Removes the lock file if it is still this holder's (never another's).
  void release() noexcept;

 private:
  OutputLock(std::filesystem::path path, std::string text)
      : path_(std::move(path)), text_(std::move(text)) {}

  std::filesystem::path path_;  // the lock file; empty when nothing is held
  std::string text_;            // what this holder wrote into it
};

}  // namespace ggk::engine
