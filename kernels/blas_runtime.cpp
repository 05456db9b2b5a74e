#include "kernels/blas_runtime.hpp"

#include <dlfcn.h>

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

BlasInfo blas_info() {
  auto* get_parallel = openblas_symbol<int()>("openblas_get_parallel");
  auto* get_config = openblas_symbol<char*()>("openblas_get_config");
  if (get_parallel == nullptr || get_config == nullptr)
    return {"libblas.so.3 (not OpenBLAS; assumed thread-safe)", true};
  const int parallel = get_parallel();  // 0 serial, 1 pthread, 2 OpenMP
  const char* build = parallel == 0 ? "serial" : parallel == 1 ? "pthread" : "openmp";
  return {std::string(get_config()) + " (" + build + " build)", parallel != 0};
}

}  // namespace ggk::kernels
