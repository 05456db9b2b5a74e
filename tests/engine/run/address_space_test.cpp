// ggk under an address-space limit (engine/run/address_space.hpp): what the
// memory check counts per thread. The restart and the refusal are tested through
// the binary (memory_check_test.cpp, UnderAnAddressSpaceLimit...).

#include "engine/run/address_space.hpp"

#include <gtest/gtest.h>

#include "kernels/blas_runtime.hpp"

namespace ggk::engine {
namespace {

TEST(AddressSpace, EachComputingThreadReservesABufferAnArenaAndAStack) {
  const double one = reserved_address_space(1);
  const double two = reserved_address_space(2);
  const double per_thread = two - one;
  // A malloc arena (64 MiB) and a stack (at least 8 MiB), plus the BLAS buffer.
  EXPECT_GE(per_thread, 72.0 * 1024 * 1024 + kernels::blas_thread_buffer_bytes());
  EXPECT_DOUBLE_EQ(reserved_address_space(16) - one, 15.0 * per_thread);
  // The writer thread: an arena and a stack beside the computing threads.
  EXPECT_GE(one - per_thread, 72.0 * 1024 * 1024);
  EXPECT_DOUBLE_EQ(reserved_address_space(0), one);  // at least one thread computes
}

TEST(AddressSpace, OpenBlasReservesItsWorkBufferPerThread) {
  if (kernels::blas_info().name.find("OpenBLAS") == std::string::npos) {
    GTEST_SKIP() << "the BLAS is not OpenBLAS";
  }
  EXPECT_EQ(kernels::blas_thread_buffer_bytes(), 128.0 * 1024 * 1024);
}

}  // namespace
}  // namespace ggk::engine
