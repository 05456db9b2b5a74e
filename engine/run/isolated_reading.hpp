#pragma once
// Reading files that may be damaged, in a child process.
//
// HDF5 1.10 does not survive every damaged object header: when an attribute
// message in the middle of an object's attribute list fails to decode,
// H5Aiterate releases the half-built attribute table and dies of SIGSEGV in
// H5A__close (1.10.8; measured: one attribute message's version byte set to 0x7f
// crashes `ggk verify` for 6 of 7 attributes tried, depending on what the
// allocator held). No check before the read can tell such a header from a whole
// one: reading it is the check.
// So every command that reads a file ggk did not just write (info, verify, diff,
// merge; run --resume's check of its output) does that reading in a forked child:
// a crash of the child is a damaged file, reported as such, and the parent is left
// to clean up (the lock, a temporary file) and exit with a clear status.
//
// The child inherits stdout and stderr (what it prints reaches the user as is),
// runs the work on its one thread (fork copies only the calling thread: nothing
// else may be inside HDF5 when this is called) and ends with _exit, so nothing of
// the parent's (atexit handlers, MPI, open HDF5 files) runs twice.

#include <sys/types.h>

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "engine/job/usage_error.hpp"

namespace ggk::engine {

// How a child process ended.
struct ChildEnd {
  pid_t pid = 0;
  int exit_status = 0;  // when it exited
  int signal = 0;       // the signal that ended it, or 0
  // What `work` threw, if anything: "usage" (UsageError, JobError), "run"
  // (RunFailure), "memory" (std::bad_alloc), "internal" (any other exception);
  // empty when it returned.
  std::string error_kind;
  std::string message;  // the exception's text
  // False when the child ended without reporting (a crash, or a sanitizer that
  // turned one into an exit): nothing it did can be trusted.
  bool reported = false;
};

// Runs `work` in a forked child and waits for it (the work bounds its own time).
// Its return value is the child's exit status. Throws std::runtime_error when no
// child can be made (fork or pipe failed).
ChildEnd run_in_child(const std::function<int()>& work);

// The child died of a signal that means a crash (SIGSEGV, SIGBUS, SIGFPE,
// SIGILL, SIGABRT, SIGSYS), or ended without a report.
bool crashed(const ChildEnd& end);

// How the child ended, in words: "SIGSEGV (Segmentation fault)", or "an exit
// (status 1) without a report".
std::string ending_words(const ChildEnd& end);

// Reads `file` whole (ggk verify's walk, output discarded) in a child: how the
// child ended says whether reading it crashes HDF5 (crashed()); what verify
// reports (damage, an error) is left to the reader that follows.
ChildEnd read_whole_in_child(const std::filesystem::path& file);

// A crash of the HDF5 library reading `file`: a UsageError (exit status 2),
// saying the file is damaged where HDF5 does not check.
class ReadingCrash : public UsageError {
 public:
  ReadingCrash(const std::string& file, const ChildEnd& end);
  const std::string& file() const { return file_; }  // or "one of A, B"
  const std::string& how() const { return how_; }    // ending_words()

 private:
  std::string file_;
  std::string how_;
};

// Runs `work`, which reads `files`, in a child and returns its exit status. What
// the work threw is thrown again here as the same kind (UsageError, RunFailure,
// std::runtime_error); std::bad_alloc (a size in a damaged or hostile file larger
// than memory) as a UsageError "not enough memory to read <files>" (exit 2). A crash calls
// `after_crash` with the child's pid (to remove what the child left) and throws ReadingCrash naming
// the file that crashes when read alone (each of several is read whole, as ggk verify does, in a
// child of its own). A child ended by any other signal (Ctrl-C reaches the whole process group;
// SIGPIPE from `ggk info | head`) ends this process by the same signal.
int read_isolated(const std::vector<std::filesystem::path>& files, const std::function<int()>& work,
                  const std::function<void(pid_t)>& after_crash = {});

}  // namespace ggk::engine
