#include "kernels/flop_count.hpp"

#include <atomic>

namespace ggk::kernels {

namespace {

std::atomic<std::uint64_t> flops_total{0};

}  // namespace

void count_flops(double flops) {
  flops_total.fetch_add(static_cast<std::uint64_t>(flops), std::memory_order_relaxed);
}

double flops_counted() {
  return static_cast<double>(flops_total.load(std::memory_order_relaxed));
}

}  // namespace ggk::kernels
