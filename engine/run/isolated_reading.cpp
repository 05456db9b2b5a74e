#include "engine/run/isolated_reading.hpp"

#include <fcntl.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <stdexcept>

#include "engine/job/job_error.hpp"
#include "engine/run/job_runner.hpp"
#include "engine/run/reading_memory_cap.hpp"
#include "engine/store/results_verify.hpp"

namespace ggk::engine {

namespace {

// The report a child sends up its pipe: "<kind>\n<message>", kind "ok" when the
// work returned.
void write_report(int fd, const std::string& kind, const std::string& message) {
  const std::string text = kind + "\n" + message;
  const char* data = text.data();
  std::size_t left = text.size();
  while (left > 0) {
    const ssize_t written = ::write(fd, data, left);
    if (written < 0 && errno == EINTR) continue;
    if (written <= 0) return;  // the parent is gone: nothing to tell
    data += written;
    left -= static_cast<std::size_t>(written);
  }
}

[[noreturn]] void child_main(int report_fd, const std::function<int()>& work) {
  int status = 0;
  std::string kind = "ok", message;
  try {
    status = work();
  } catch (const UsageError& e) {
    kind = "usage", message = e.what(), status = 2;
  } catch (const JobError& e) {
    kind = "usage", message = e.what(), status = 2;
  } catch (const RunFailure& e) {
    kind = "run", message = e.what(), status = 1;
  } catch (const std::bad_alloc&) {  // a size in a file larger than memory: no bug of ggk's
    kind = "memory", status = 2;
  } catch (const std::exception& e) {
    kind = "internal", message = e.what(), status = 1;
  } catch (...) {
    kind = "internal", message = "an exception of unknown type", status = 1;
  }
  std::cout.flush();
  std::cerr.flush();
  std::fflush(nullptr);
  write_report(report_fd, kind, message);
  ::_exit(status);
}

// The child is a reader, not `ggk run`: a stop signal ends it plainly (the
// parent's handler, stop_signals.hpp, is the parent's: the child must not remove
// the parent's lock or print its resume command), and it dies with the thread
// that forked it (a SIGTERM or SIGKILL sent to the parent's pid alone would
// otherwise leave it reading on as an orphan).
void become_reader_child(pid_t parent) {
  for (const int signal : {SIGINT, SIGTERM, SIGHUP}) {
    struct sigaction current {};
    ::sigaction(signal, nullptr, &current);
    if (current.sa_handler == SIG_IGN) continue;  // an inherited SIG_IGN stays
    struct sigaction plain {};
    plain.sa_handler = SIG_DFL;
    sigemptyset(&plain.sa_mask);
    ::sigaction(signal, &plain, nullptr);
  }
  ::prctl(PR_SET_PDEATHSIG, SIGKILL);
  if (::getppid() != parent) ::_exit(1);  // the parent died before prctl
}

std::string signal_words(int signal) {
  const char* name = sigabbrev_np(signal);
  const char* description = strsignal(signal);
  return std::string("SIG") + (name != nullptr ? name : std::to_string(signal)) + " (" +
         (description != nullptr ? description : "unknown signal") + ")";
}

}  // namespace

ChildEnd run_in_child(const std::function<int()>& work) {
  // What the parent has buffered must not be printed twice (once by the child).
  std::cout.flush();
  std::cerr.flush();
  std::fflush(nullptr);
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0) {
    throw std::runtime_error(std::string("cannot make a pipe: ") + std::strerror(errno));
  }
  const pid_t parent = ::getpid();
  const pid_t pid = ::fork();
  if (pid < 0) {
    const int error = errno;
    ::close(fds[0]);
    ::close(fds[1]);
    throw std::runtime_error(std::string("cannot start a child process: ") + std::strerror(error));
  }
  if (pid == 0) {
    ::close(fds[0]);
    become_reader_child(parent);
    child_main(fds[1], work);
  }
  ::close(fds[1]);
  std::string report;
  char buffer[4096];
  for (;;) {  // ends when the child exits (its end of the pipe closes)
    const ssize_t got = ::read(fds[0], buffer, sizeof buffer);
    if (got < 0 && errno == EINTR) continue;
    if (got <= 0) break;
    report.append(buffer, static_cast<std::size_t>(got));
  }
  ::close(fds[0]);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) {
      throw std::runtime_error(std::string("cannot wait for a child process: ") +
                               std::strerror(errno));
    }
  }
  ChildEnd end;
  end.pid = pid;
  if (WIFSIGNALED(status)) {
    end.signal = WTERMSIG(status);
  } else {
    end.exit_status = WEXITSTATUS(status);
  }
  const std::size_t newline = report.find('\n');
  if (newline != std::string::npos) {
    end.reported = true;
    end.error_kind = report.substr(0, newline);
    if (end.error_kind == "ok") end.error_kind.clear();
    end.message = report.substr(newline + 1);
  }
  return end;
}

bool crashed(const ChildEnd& end) {
  switch (end.signal) {
    case SIGSEGV:
    case SIGBUS:
    case SIGFPE:
    case SIGILL:
    case SIGABRT:
    case SIGSYS:
      return true;
    case 0:
      return !end.reported;
    default:
      return false;
  }
}

std::string ending_words(const ChildEnd& end) {
  return end.signal != 0
             ? signal_words(end.signal)
             : "an exit (status " + std::to_string(end.exit_status) + ") without a report";
}

ReadingCrash::ReadingCrash(const std::string& file, const ChildEnd& end)
    : UsageError("reading " + file + " crashed the HDF5 library (" + ending_words(end) +
                 "): it is damaged in an object header, where HDF5 does not check before "
                 "it reads, and ggk cannot read it; nothing was written"),
      file_(file),
      how_(ending_words(end)) {}

ChildEnd read_whole_in_child(const std::filesystem::path& file) {
  const ReadingRoom room = ReadingRoom::for_files({file});
  return run_in_child([&] {
    const ReadingMemoryCap cap(room);
    std::ostream quiet(nullptr);
    try {
      verify_results(file, quiet);
    } catch (const std::exception&) {  // an error is an answer, not a crash
    }
    return 0;
  });
}

namespace {

// The file of `files` whose whole reading crashes, or "one of A, B" when none
// does alone.
std::string crashing_file(const std::vector<std::filesystem::path>& files) {
  if (files.size() == 1) return files.front().string();
  std::string names;
  for (const std::filesystem::path& file : files) {
    if (crashed(read_whole_in_child(file))) return file.string();
    names += (names.empty() ? "" : ", ") + file.string();
  }
  return "one of " + names;
}

std::string names_of(const std::vector<std::filesystem::path>& files) {
  std::string names;
  for (std::size_t i = 0; i < files.size(); ++i) {
    names += (i == 0 ? "" : i + 1 == files.size() ? " or " : ", ") + files[i].string();
  }
  return names;
}

}  // namespace

int read_isolated(const std::vector<std::filesystem::path>& files, const std::function<int()>& work,
                  const std::function<void(pid_t)>& after_crash) {
  const ReadingRoom room = ReadingRoom::for_files(files);
  const ChildEnd end = run_in_child([&] {
    const ReadingMemoryCap cap(room);
    return work();
  });
  if (crashed(end) && room.user_limit_binds) {
    // HDF5 does not survive every failed allocation: under the user's tight
    // limit a crash says nothing about the file.
    if (after_crash) after_crash(end.pid);
    throw UsageError("not enough memory to read " + names_of(files) + " under " +
                     room.limit_words(names_of(files)) + ": reading crashed (" + ending_words(end) +
                     "), as HDF5 does when memory runs out; raise the limit (or lift it) to "
                     "read the file, or to tell whether it is damaged");
  }
  if (crashed(end)) {
    if (after_crash) after_crash(end.pid);
    throw ReadingCrash(crashing_file(files), end);
  }
  if (end.signal != 0) {  // Ctrl-C, SIGTERM, SIGPIPE: end as the child did
    std::cout.flush();
    std::signal(end.signal, SIG_DFL);
    std::raise(end.signal);
    std::_Exit(128 + end.signal);
  }
  if (end.error_kind == "memory" && room.user_limit_binds) {
    throw UsageError("not enough memory to read " + names_of(files) + " under " +
                     room.limit_words(names_of(files)) + ": raise the limit (or lift it)");
  }
  if (end.error_kind == "memory") {
    throw UsageError("not enough memory to read " + names_of(files) +
                     ": this machine could not allocate what reading it takes");
  }
  if (end.error_kind == "usage") throw UsageError(end.message);
  if (end.error_kind == "run") throw RunFailure(end.message);
  if (end.error_kind == "internal") throw std::runtime_error(end.message);
  return end.exit_status;
}

}  // namespace ggk::engine
