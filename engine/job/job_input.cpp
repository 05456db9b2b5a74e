#include "engine/job/job_input.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "engine/job/toml_table_reader.hpp"
#include "engine/single_quoted.hpp"

namespace ggk::engine {
namespace {

// "is a FIFO (named pipe), not a regular file" and the like, for a stat mode
// that is not a regular file.
std::string type_problem(mode_t mode) {
  if (S_ISDIR(mode)) return "is a directory";
  const char* type = S_ISFIFO(mode)   ? "a FIFO (named pipe)"
                     : S_ISCHR(mode)  ? "a character device"
                     : S_ISBLK(mode)  ? "a block device"
                     : S_ISSOCK(mode) ? "a socket"
                                      : "of an unknown type";
  return std::string("is ") + type + ", not a regular file";
}

std::string size_problem(std::int64_t size, std::int64_t max_bytes) {
  constexpr std::int64_t kMiB = std::int64_t{1024} * 1024;
  const std::string limit = max_bytes % kMiB == 0 && max_bytes > 0
                                ? std::to_string(max_bytes / kMiB) + " MiB"
                                : std::to_string(max_bytes) + " bytes";
  return "is " + std::to_string(size) + " bytes, more than the limit of " + limit +
         " for a job file or a file it names";
}

// Why a file of this kind and size cannot be read (type_problem, size_problem),
// or "" for a regular file of at most max_bytes.
std::string kind_or_size_problem(const struct stat& info, std::int64_t max_bytes) {
  if (!S_ISREG(info.st_mode)) return type_problem(info.st_mode);
  if (info.st_size > max_bytes) return size_problem(info.st_size, max_bytes);
  return "";
}

// Why stat(2) or open(2) failed, for error number `error` on `path`.
std::string open_problem(int error, const std::filesystem::path& path) {
  switch (error) {
    case ENOENT: {
      // A symlink whose target is missing reads as missing itself; say which.
      struct stat link {};
      if (::lstat(path.c_str(), &link) == 0 && S_ISLNK(link.st_mode)) {
        return "is a symbolic link to a file that does not exist";
      }
      return "does not exist";
    }
    case ELOOP:
      return "is a symbolic link loop (too many levels of symbolic links)";
    case ENOTDIR:
      return "does not exist (a component of its path is not a directory)";
    default:
      return std::string("cannot be read: ") + std::strerror(error);
  }
}

// Closes a descriptor on every path out of read_regular_file().
class Descriptor {
 public:
  explicit Descriptor(int fd) : fd_(fd) {}
  Descriptor(const Descriptor&) = delete;
  Descriptor& operator=(const Descriptor&) = delete;
  ~Descriptor() {
    if (fd_ >= 0) ::close(fd_);
  }
  int get() const { return fd_; }

 private:
  int fd_;
};

}  // namespace

RegularFileText read_regular_file(const std::filesystem::path& path, std::int64_t max_bytes) {
  RegularFileText result;
  // First by name: nothing is opened that is not a regular file of a sane size
  // (opening a FIFO without O_NONBLOCK waits for a writer).
  struct stat info {};
  if (::stat(path.c_str(), &info) != 0) {
    result.problem = open_problem(errno, path);
    return result;
  }
  result.problem = kind_or_size_problem(info, max_bytes);
  if (!result.problem.empty()) return result;
  // Then by descriptor: the name may have been replaced since.
  const Descriptor file(::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY));
  if (file.get() < 0) {
    result.problem = open_problem(errno, path);
    return result;
  }
  if (::fstat(file.get(), &info) != 0) {
    result.problem = std::string("cannot be read: ") + std::strerror(errno);
    return result;
  }
  result.problem = kind_or_size_problem(info, max_bytes);
  if (!result.problem.empty()) return result;
  // Read at most max_bytes + 1 bytes: a file that grows while it is read is
  // refused rather than followed.
  std::string text;
  text.resize(static_cast<std::size_t>(info.st_size) + 1);
  std::size_t filled = 0;
  for (;;) {
    if (filled == text.size()) {
      if (static_cast<std::int64_t>(filled) > max_bytes) {
        result.problem = size_problem(static_cast<std::int64_t>(filled), max_bytes) +
                         " (it grew while it was read)";
        return result;
      }
      text.resize(std::min<std::size_t>(text.size() * 2, static_cast<std::size_t>(max_bytes) + 1));
    }
    const ssize_t got = ::read(file.get(), text.data() + filled, text.size() - filled);
    if (got < 0) {
      if (errno == EINTR) continue;
      result.problem = std::string("cannot be read: ") + std::strerror(errno);
      return result;
    }
    if (got == 0) break;
    filled += static_cast<std::size_t>(got);
  }
  text.resize(filled);
  result.text = std::move(text);
  return result;
}

std::filesystem::path project_jobs_dir() {
#ifdef GGK_PROJECT_JOBS_DIR
  return GGK_PROJECT_JOBS_DIR;
#else
  return {};
#endif
}

JobInput read_job_input(const TomlTableReader& table, std::string_view key,
                        const std::filesystem::path& job_dir, const std::string& name,
                        std::string_view what) {
  const std::filesystem::path path = job_dir / name;
  JobInput input{table.key_path(key), path.lexically_normal().string(), {}};
  RegularFileText file = read_regular_file(path);
  // A job copied out of the project (to start one's own) still finds the maps and
  // arenas the project ships: a relative name missing beside the job is looked
  // up in the project's jobs/ folder next.
  std::string elsewhere;
  const std::filesystem::path shipped = project_jobs_dir();
  if (file.problem == "does not exist" && std::filesystem::path(name).is_relative() &&
      !shipped.empty()) {
    const std::filesystem::path second = (shipped / name).lexically_normal();
    RegularFileText found = read_regular_file(second);
    if (found.problem.empty()) {
      input.path = second.string();
      file = std::move(found);
    } else {
      elsewhere = ", nor is " + shortened(second.string()) + " in the project's jobs/ folder (" +
                  found.problem + ")";
    }
  }
  if (!file.problem.empty()) {
    table.fail(key, std::string(what) + " " + single_quoted(shortened(name)) + " (" +
                        shortened(input.path) + ") " + file.problem + elsewhere);
  }
  input.text = std::move(file.text);
  return input;
}

}  // namespace ggk::engine
