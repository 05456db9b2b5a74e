#pragma once
// The BLAS behind Eigen's dense products (EIGEN_USE_BLAS), CHOLMOD and UMFPACK is
// whatever libblas.so.3 resolves to at run time, and the LAPACK of the dense LSPI
// solves whatever liblapack.so.3 does; on Debian both are alternatives, OpenBLAS
// in the install (scripts/install-deps.sh). ggk calls it from many TBB
// tasks at once, so it needs a BLAS that
//   - is safe to call concurrently: OpenBLAS's pthread build or the reference BLAS;
//     Debian 12's serial OpenBLAS is not (it is built without locking: concurrent
//     calls share work buffers and return wrong numbers), and
//   - runs each call on the calling thread: threads inside a call would compete
//     with TBB's and make results depend on how the call was split.
// use_calling_thread_blas() sets OpenBLAS to one thread per call (found with dlsym,
// so any libblas.so.3 works); the kernels that reach the BLAS call it first.

#include <string>

namespace ggk::kernels {

struct BlasInfo {
  // e.g. "OpenBLAS 0.3.21 ... Zen MAX_THREADS=64 (pthread build); LAPACK from
  // /usr/lib/x86_64-linux-gnu/openblas-pthread/liblapack.so.3" (the library that
  // resolved dgetrf_: the dense LSPI solves' bits depend on it as on the BLAS)
  std::string name;
  bool concurrent_safe = true;  // false for a serial OpenBLAS built without locking
};

// Idempotent and thread-safe; cheap after the first call.
void use_calling_thread_blas();

BlasInfo blas_info();

// The threads OpenBLAS's pthread build started when it was loaded (its thread
// pool: OPENBLAS_NUM_THREADS, else the CPUs, less the caller); 0 for another
// BLAS. Meaningful before use_calling_thread_blas(), which changes what OpenBLAS
// reports but stops no thread. Each of them takes a level-3 work buffer at start
// and retries a failed allocation forever (OpenBLAS 0.3.21, memory.c), so under
// an address-space limit they can spin and keep the process from exiting.
int blas_pool_threads();

// The address space one thread's first level-3 call reserves for its work buffer
// (OpenBLAS: BUFFER_SIZE, 128 MiB on x86-64, mapped once per concurrent caller
// and kept); 0 for another BLAS.
double blas_thread_buffer_bytes();

}  // namespace ggk::kernels
