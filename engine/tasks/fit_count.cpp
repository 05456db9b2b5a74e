#include "engine/tasks/fit_count.hpp"

#include <atomic>

namespace ggk::engine {

namespace {
std::atomic<std::int64_t> g_fits_done{0};
}  // namespace

void count_fit_done() {
  g_fits_done.fetch_add(1, std::memory_order_relaxed);
}

std::int64_t fits_done() {
  return g_fits_done.load(std::memory_order_relaxed);
}

}  // namespace ggk::engine
