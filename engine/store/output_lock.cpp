#include "engine/store/output_lock.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <optional>
#include <sstream>
#include <utility>

#include "engine/job/usage_error.hpp"
#include "engine/store/process_state.hpp"
#include "engine/store/utc_time.hpp"

namespace ggk::engine {

namespace fs = std::filesystem;

namespace {

constexpr int kAttempts = 8;

std::string host_name() {
  char buffer[256] = {};
  if (::gethostname(buffer, sizeof buffer - 1) != 0) return "unknown-host";
  return buffer;
}

std::optional<std::string> read_text(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return std::nullopt;
  return std::string{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// What is wrong with the thing at the lock's path when it cannot be a ggk
// lock file (a directory, a device, a symbolic link to nothing or to one of
// those); nullopt for a regular file, or when nothing is there any more.
std::optional<std::string> not_a_lock_file(const fs::path& lock) {
  struct stat link_status {};
  if (::lstat(lock.c_str(), &link_status) != 0) return std::nullopt;
  struct stat status {};
  if (S_ISLNK(link_status.st_mode)) {
    if (::stat(lock.c_str(), &status) != 0) return "a symbolic link to nothing";
    if (S_ISREG(status.st_mode)) return std::nullopt;
    return S_ISDIR(status.st_mode) ? "a symbolic link to a directory"
                                   : "a symbolic link to something that is not a file";
  }
  if (S_ISREG(link_status.st_mode)) return std::nullopt;
  return S_ISDIR(link_status.st_mode) ? "a directory" : "not a regular file";
}

struct Holder {
  std::string host;
  pid_t pid = 0;
  std::string process_start;
  std::string since;
};

Holder parse_holder(const std::string& text) {
  Holder holder;
  std::istringstream lines(text);
  std::string line;
  while (std::getline(lines, line)) {
    const std::size_t eq = line.find('=');
    if (eq == std::string::npos) continue;
    const std::string key = line.substr(0, eq), value = line.substr(eq + 1);
    if (key == "host") holder.host = value;
    if (key == "process_start") holder.process_start = value;
    if (key == "since") holder.since = value;
    if (key == "pid") holder.pid = static_cast<pid_t>(std::atol(value.c_str()));
  }
  return holder;
}

// True when the holder is known to be gone: it ran on this host and no process
// with its pid (and start time) exists any more, or only its zombie does (it
// has exited; its parent has not reaped it yet: the ranks of an mpirun that
// stopped on Ctrl-C, for some milliseconds after mpirun has returned).
bool holder_is_gone(const Holder& holder) {
  if (holder.pid <= 0 || holder.host != host_name()) return false;
  if (!process_alive(holder.pid)) return true;
  const std::string start = process_start(holder.pid);
  return !holder.process_start.empty() && !start.empty() && start != holder.process_start;
}

std::string holder_message(const fs::path& results, const fs::path& lock, const Holder& holder) {
  if (holder.pid <= 0) {
    return "output " + results.string() + " is locked by " + lock.string() +
           ", which is not a ggk lock or was left half written; if no ggk is writing " +
           results.string() + ", remove " + lock.string();
  }
  return "output " + results.string() + " is being written by another ggk (pid " +
         std::to_string(holder.pid) + " on host " + holder.host + ", since " + holder.since +
         "; lock file " + lock.string() + "): wait for it to finish, or, if no ggk runs there " +
         "any more, remove " + lock.string();
}

// Writes `text` to a new file at `path` (exclusive create), synced.
bool write_new_file(const fs::path& path, const std::string& text) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
  if (fd < 0) return false;
  const bool ok = ::write(fd, text.data(), text.size()) == static_cast<ssize_t>(text.size()) &&
                  ::fsync(fd) == 0;
  const int saved = errno;
  ::close(fd);
  if (!ok) {
    ::unlink(path.c_str());
    errno = saved;
  }
  return ok;
}

[[noreturn]] void throw_cannot_lock(const fs::path& results, const fs::path& lock,
                                    const std::string& why) {
  throw UsageError("output " + results.string() + ": cannot create its lock file " + lock.string() +
                   ": " + why);
}

// Places `text` at `lock` only if no lock file exists there: true on success,
// false when one exists (EEXIST); throws on any other failure.
bool create_lock(const fs::path& results, const fs::path& lock, const fs::path& scratch,
                 const std::string& text) {
  if (::link(scratch.c_str(), lock.c_str()) == 0) return true;
  if (errno == EEXIST) return false;
  if (errno == EPERM || errno == ENOSYS || errno == EOPNOTSUPP) {
    // A file system without hard links: an exclusive create is the next best.
    if (write_new_file(lock, text)) return true;
    if (errno == EEXIST) return false;
  }
  throw_cannot_lock(results, lock, std::strerror(errno));
}

}  // namespace

std::optional<std::string> OutputLock::writer_of(const fs::path& results) {
  const std::optional<std::string> text = read_text(path_for(results));
  if (!text) return std::nullopt;
  const Holder holder = parse_holder(*text);
  if (holder.pid <= 0 || holder_is_gone(holder)) return std::nullopt;
  return "ggk pid " + std::to_string(holder.pid) + " on host " + holder.host + ", since " +
         holder.since;
}

fs::path OutputLock::path_for(const fs::path& results) {
  return fs::path(results.string() + ".lock");
}

OutputLock OutputLock::acquire(const fs::path& results) {
  const fs::path lock = path_for(results);
  const pid_t pid = ::getpid();
  const std::string host = host_name();
  const std::string text = "ggk output lock\nhost=" + host + "\npid=" + std::to_string(pid) +
                           "\nprocess_start=" + process_start(pid) + "\nsince=" + utc_now() + "\n";
  const fs::path scratch = lock.string() + "." + host + "." + std::to_string(pid);
  ::unlink(scratch.c_str());  // a leftover of this very pid's predecessor
  if (!write_new_file(scratch, text)) throw_cannot_lock(results, lock, std::strerror(errno));
  struct RemoveScratch {
    const fs::path& path;
    ~RemoveScratch() { ::unlink(path.c_str()); }
  } remove_scratch{scratch};

  for (int attempt = 0; attempt < kAttempts; ++attempt) {
    if (create_lock(results, lock, scratch, text)) return OutputLock(lock, text);
    if (const std::optional<std::string> problem = not_a_lock_file(lock)) {
      throw UsageError("output " + results.string() + ": its lock path " + lock.string() + " is " +
                       *problem +
                       ", not a ggk lock file: remove or rename it (a lock holds no "
                       "results), or write to another -o");
    }
    const std::optional<std::string> existing = read_text(lock);
    if (!existing) continue;  // released meanwhile: try again
    const Holder holder = parse_holder(*existing);
    if (!holder_is_gone(holder)) throw UsageError(holder_message(results, lock, holder));
    // A stale lock: move it aside, then check that what moved is the lock judged
    // stale (another ggk may have taken it over in between: put that one back).
    const fs::path aside = lock.string() + ".stale." + host + "." + std::to_string(pid);
    if (::rename(lock.c_str(), aside.c_str()) != 0) continue;
    if (read_text(aside) != existing) (void)::link(aside.c_str(), lock.c_str());
    ::unlink(aside.c_str());
  }
  throw UsageError("output " + results.string() + ": could not take its lock " + lock.string() +
                   " in " + std::to_string(kAttempts) +
                   " attempts (other ggk processes keep taking it)");
}

OutputLock::OutputLock(OutputLock&& other) noexcept
    : path_(std::exchange(other.path_, {})), text_(std::exchange(other.text_, {})) {}

OutputLock& OutputLock::operator=(OutputLock&& other) noexcept {
  if (this != &other) {
    release();
    path_ = std::exchange(other.path_, {});
    text_ = std::exchange(other.text_, {});
  }
  return *this;
}

OutputLock::~OutputLock() {
  release();
}

void OutputLock::release() noexcept {
  if (path_.empty()) return;
  try {
    if (read_text(path_) == text_) ::unlink(path_.c_str());
  } catch (...) {  // never throw from a release (bad_alloc reading the file)
  }
  path_.clear();
  text_.clear();
}

}  // namespace ggk::engine
