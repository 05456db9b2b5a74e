#include "kernels/blas_runtime.hpp"

#include <dlfcn.h>
#include <limits.h>
#include <stdlib.h>

#include <mutex>

namespace ggk::kernels {
namespace {

// OpenBLAS's own entry points; absent from other BLAS libraries.
template <typename Function>
Function* openblas_symbol(const char* name) {
  return reinterpret_cast<Function*>(dlsym(RTLD_DEFAULT, name));
}

}  // namespace

void use_calling_thread_blas() {
  static std::once_flag once;
  std::call_once(once, [] {
    if (auto* set_threads = openblas_symbol<void(int)>("openblas_set_num_threads")) {
      set_threads(1);
    }
  });
}

std::string lapack_library() {
  void* dgetrf = dlsym(RTLD_DEFAULT, "dgetrf_");
  Dl_info info{};
  if (dgetrf == nullptr || dladdr(dgetrf, &info) == 0 || info.dli_fname == nullptr) {
    return "unknown";
  }
  // The file behind the name: liblapack.so.3 is a chain of links to Debian's
  // alternative (OpenBLAS's LAPACK, or the reference one).
  char resolved[PATH_MAX];
  return realpath(info.dli_fname, resolved) != nullptr ? resolved : info.dli_fname;
}

int blas_pool_threads() {
  auto* get_threads = openblas_symbol<int()>("openblas_get_num_threads");
  auto* get_parallel = openblas_symbol<int()>("openblas_get_parallel");
  if (get_threads == nullptr || get_parallel == nullptr || get_parallel() != 1) return 0;
  return get_threads() > 1 ? get_threads() - 1 : 0;
}

double blas_thread_buffer_bytes() {
  return openblas_symbol<int()>("openblas_get_parallel") != nullptr ? 128.0 * 1024 * 1024 : 0.0;
}

BlasInfo blas_info() {
  auto* get_parallel = openblas_symbol<int()>("openblas_get_parallel");
  auto* get_config = openblas_symbol<char*()>("openblas_get_config");
  const std::string lapack = "; LAPACK from " + lapack_library();
  if (get_parallel == nullptr || get_config == nullptr)
    return {"libblas.so.3 (not OpenBLAS; assumed thread-safe)" + lapack, true};
  const int parallel = get_parallel();  // 0 serial, 1 pthread, 2 OpenMP
  const char* build = parallel == 0 ? "serial" : parallel == 1 ? "pthread" : "openmp";
  return {std::string(get_config()) + " (" + build + " build)" + lapack, parallel != 0};
}

}  // namespace ggk::kernels
