#pragma once
// Whether a process of this host is still running: rank 0 asks it of a worker on
// its own host that has not reported a stop signal, to tell a worker that is slow
// to answer (a loaded machine) from one that died (mpi_runner.cpp).
//
// Thread-safety: reentrant.
#include <sys/types.h>

namespace ggk::engine {

// True when `pid` names a process that runs (or sleeps): not when there is none,
// and not when it has exited and waits to be reaped (a zombie: it died).
bool process_alive(pid_t pid);

}  // namespace ggk::engine
