#pragma once
// The output of `ggk run`: where a job's results go, checked before anything is
// written (the directory exists and is writable; the path is absent, empty or a
// regular file), and held for as long as the job writes (ResultsTarget: the
// output lock, and the "<output>.part" file a new results file is written under
// until its first run lands, then renamed into place). open_results.hpp says
// when each is used.

#include <filesystem>

#include "engine/hdf5/hdf5_file.hpp"
#include "engine/store/output_lock.hpp"

namespace ggk::engine {

// Where a job's results go, and the lock on it, for as long as the job writes.
class ResultsTarget {
 public:
  ResultsTarget() = default;
  ResultsTarget(std::filesystem::path output, std::filesystem::path temporary, OutputLock lock);
  ResultsTarget(ResultsTarget&& other) noexcept;
  ResultsTarget& operator=(ResultsTarget&&) = delete;
  ResultsTarget(const ResultsTarget&) = delete;
  ResultsTarget& operator=(const ResultsTarget&) = delete;
  // Removes a temporary file that never took the output's name; releases the lock.
  ~ResultsTarget();

  const std::filesystem::path& output() const { return output_; }
  // The file being written: output(), or "<output>.part" until publish().
  const std::filesystem::path& writing_to() const;
  // "<output>.part" until publish(); empty when resuming or published.
  const std::filesystem::path& temporary() const { return temporary_; }
  std::filesystem::path lock_file() const { return OutputLock::path_for(output_); }
  // For a process about to exit at once (_Exit): removes the lock file now.
  void release_lock() { lock_.release(); }

  // Gives a file written under the temporary name the output's name (rename);
  // nothing when it has it already. Call after a run is written and flushed, on
  // the thread that writes `file` (whose path it updates).
  void publish(Hdf5File& file);

 private:
  std::filesystem::path output_;
  std::filesystem::path temporary_;  // empty once published, or when resuming
  OutputLock lock_;
};

// What is at the output path now: nothing, an empty file, or a file with bytes.
enum class OutputState { kAbsent, kEmpty, kFile };

// The state of `output`; anything but a regular file (a directory, /dev/null, a
// FIFO) is a UsageError, as is a path stat cannot read.
OutputState output_state(const std::filesystem::path& output);

// A UsageError when the output's directory does not exist or is not writable.
void check_output_directory(const std::filesystem::path& output);

// "<output>.part": where a new results file is written until its first run lands.
std::filesystem::path temporary_results_path(const std::filesystem::path& output);

}  // namespace ggk::engine
