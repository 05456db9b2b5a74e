#include "engine/run/results_target.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <system_error>
#include <utility>

#include "engine/job/usage_error.hpp"

namespace ggk::engine {

namespace fs = std::filesystem;

void check_output_directory(const fs::path& output) {
  const fs::path dir = output.parent_path().empty() ? fs::path(".") : output.parent_path();
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) {
    throw UsageError("output " + output.string() + ": directory " + dir.string() +
                     " does not exist");
  }
  if (access(dir.c_str(), W_OK) != 0) {
    throw UsageError("output " + output.string() + ": directory " + dir.string() +
                     " is not writable");
  }
}

OutputState output_state(const fs::path& output) {
  struct stat status {};
  if (::stat(output.c_str(), &status) != 0) {
    if (errno == ENOENT) return OutputState::kAbsent;
    throw UsageError("output " + output.string() + ": " + std::strerror(errno));
  }
  if (S_ISDIR(status.st_mode)) throw UsageError("output " + output.string() + " is a directory");
  if (!S_ISREG(status.st_mode)) {
    throw UsageError("output " + output.string() +
                     " is not a regular file (a device, FIFO or socket): results go to a file");
  }
  return status.st_size == 0 ? OutputState::kEmpty : OutputState::kFile;
}

fs::path temporary_results_path(const fs::path& output) {
  return fs::path(output.string() + ".part");
}

ResultsTarget::ResultsTarget(fs::path output, fs::path temporary, OutputLock lock)
    : output_(std::move(output)), temporary_(std::move(temporary)), lock_(std::move(lock)) {}

ResultsTarget::ResultsTarget(ResultsTarget&& other) noexcept
    : output_(std::move(other.output_)),
      temporary_(std::exchange(other.temporary_, {})),
      lock_(std::move(other.lock_)) {}

ResultsTarget::~ResultsTarget() {
  if (!temporary_.empty()) ::unlink(temporary_.c_str());
}

const fs::path& ResultsTarget::writing_to() const {
  return temporary_.empty() ? output_ : temporary_;
}

void ResultsTarget::publish(Hdf5File& file) {
  if (temporary_.empty()) return;
  if (::rename(temporary_.c_str(), output_.c_str()) != 0) {
    throw std::runtime_error("cannot rename " + temporary_.string() + " to " + output_.string() +
                             ": " + std::strerror(errno));
  }
  temporary_.clear();
  file.renamed_to(output_);
}

}  // namespace ggk::engine
