#pragma once
// What /proc says of a process of this host: whether it still runs, and when it
// started. The output lock asks it of a lock's holder (a stale lock is taken over),
// rank 0 of a worker that has not reported a stop signal (slow, or dead:
// run/mpi_runner.cpp).
//
// Thread-safety: reentrant.
#include <sys/types.h>

#include <string>

namespace ggk::engine {

// False when no process has this pid (kill(2): ESRCH) or it has exited and waits
// to be reaped (a zombie: it died); true otherwise, also when /proc cannot say
// (a process of another user, a system without /proc).
bool process_alive(pid_t pid);

// The process's start time in clock ticks since boot (/proc/<pid>/stat, field
// 22): with the pid it names one process even when pids are reused. Empty when
// unknown.
std::string process_start(pid_t pid);

}  // namespace ggk::engine
