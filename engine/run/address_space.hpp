#pragma once
// ggk under an address-space limit (ulimit -v, RLIMIT_AS: common on shared login
// nodes and in some batch systems). Two things count there that are not memory:
//   - OpenBLAS's thread pool, started when the library loads (before main), gives
//     each thread a 128 MiB work buffer and retries a failed allocation forever, so
//     a tight limit leaves a thread spinning at 100 % CPU and `exit` waiting for it;
//   - every computing thread reserves address space it may never touch: its
//     OpenBLAS buffer, glibc's malloc arena, its stack.
// ggk does not use the pool (use_calling_thread_blas: one thread per call), so
// under a finite limit it restarts itself once with OPENBLAS_NUM_THREADS=1 before
// the pool can matter, and the memory check counts the reservations against the
// limit (memory_check.hpp). Thread-safe: no state.

#include <cstdint>
#include <string>

namespace ggk::engine {

// When RLIMIT_AS is finite and OpenBLAS started a thread pool, executes
// /proc/self/exe again with the same arguments and OPENBLAS_NUM_THREADS=1, so
// the new image has no pool; returns when there is nothing to do or the exec
// fails (then the process goes on as it is). Call first thing in main, before any
// thread of ggk's own, MPI or file exists: the process keeps its PID, arguments,
// signals' dispositions and descriptors.
void restart_without_blas_pool(char** argv);

// The address space `compute_threads` computing threads and the writer thread
// reserve beyond what the job's estimate counts: per computing thread a BLAS work
// buffer (kernels::blas_thread_buffer_bytes), a malloc arena (glibc: 64 MiB on
// 64-bit, HEAP_MAX_SIZE) and a stack (RLIMIT_STACK, 8 MiB when unlimited); the
// writer thread an arena and a stack. Measured: jobs/ci.toml's VmPeak is 371 MB at
// -j 1 and 572 MB at -j 2 (~200 MB a thread), for a 5 MB estimate per run.
double reserved_address_space(std::int32_t compute_threads);

// The process's address space in use, in bytes (/proc/self/statm), 0 when unknown.
double address_space_in_use();

// " under the address-space limit of 120 MB (ulimit -v)" when RLIMIT_AS is
// finite, else "": what a message about a failed allocation adds.
std::string address_space_limit_words();

}  // namespace ggk::engine
