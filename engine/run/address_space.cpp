#include "engine/run/address_space.hpp"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <fstream>

#include "engine/tasks/run_memory.hpp"
#include "kernels/blas_runtime.hpp"

namespace ggk::engine {
namespace {

constexpr double kMallocArenaBytes = 64.0 * 1024 * 1024;  // glibc's HEAP_MAX_SIZE (64-bit)
constexpr double kDefaultStackBytes = 8.0 * 1024 * 1024;

bool address_space_limited() {
  rlimit limit{};
  return ::getrlimit(RLIMIT_AS, &limit) == 0 && limit.rlim_cur != RLIM_INFINITY;
}

double stack_bytes() {
  rlimit limit{};
  if (::getrlimit(RLIMIT_STACK, &limit) != 0 || limit.rlim_cur == RLIM_INFINITY) {
    return kDefaultStackBytes;
  }
  return std::max(static_cast<double>(limit.rlim_cur), kDefaultStackBytes);
}

}  // namespace

void restart_without_blas_pool(char** argv) {
  if (!address_space_limited() || kernels::blas_pool_threads() == 0) return;
  // Once: an image that still has a pool with the variable set (another BLAS
  // reading other variables) must not restart again.
  const char* set = std::getenv("OPENBLAS_NUM_THREADS");
  if (set != nullptr && std::strcmp(set, "1") == 0) return;
  if (::setenv("OPENBLAS_NUM_THREADS", "1", 1) != 0) return;
  ::execv("/proc/self/exe", argv);  // returns only on failure: go on with the pool
}

double reserved_address_space(std::int32_t compute_threads) {
  const double per_thread = kMallocArenaBytes + stack_bytes();
  return std::max(compute_threads, 1) * (per_thread + kernels::blas_thread_buffer_bytes()) +
         per_thread;
}

double address_space_in_use() {
  std::ifstream statm("/proc/self/statm");
  double pages = 0;
  if (!(statm >> pages)) return 0;
  return pages * static_cast<double>(::sysconf(_SC_PAGESIZE));
}

std::string address_space_limit_words() {
  rlimit limit{};
  if (::getrlimit(RLIMIT_AS, &limit) != 0 || limit.rlim_cur == RLIM_INFINITY) return "";
  return " under the address-space limit of " + format_bytes(static_cast<double>(limit.rlim_cur)) +
         " (ulimit -v)";
}

}  // namespace ggk::engine
