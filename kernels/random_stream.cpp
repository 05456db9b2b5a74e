#include "kernels/random_stream.hpp"

#include <cassert>
#include <cmath>
#include <numbers>
#include <utility>

#include <Random123/philox.h>

namespace ggk::kernels {

RandomStream::RandomStream(std::uint64_t seed, std::uint32_t stream, std::uint32_t purpose)
    : key_{static_cast<std::uint32_t>(seed), static_cast<std::uint32_t>(seed >> 32)},
      // Counter words 0-1 are the block index; words 2-3 select the stream.
      counter_{0, 0, stream, purpose} {}

void RandomStream::refill() {
  r123::Philox4x32 generator;
  const r123::Philox4x32::ctr_type counter = {{counter_[0], counter_[1], counter_[2], counter_[3]}};
  const r123::Philox4x32::key_type key = {{key_[0], key_[1]}};
  const r123::Philox4x32::ctr_type out = generator(counter, key);
  block_[0] = (static_cast<std::uint64_t>(out.v[1]) << 32) | out.v[0];
  block_[1] = (static_cast<std::uint64_t>(out.v[3]) << 32) | out.v[2];
  available_ = 2;
  if (++counter_[0] == 0) ++counter_[1];
}

std::uint64_t RandomStream::next_u64() {
  if (available_ == 0) refill();
  return block_[2 - available_--];
}

double RandomStream::uniform() {
  return static_cast<double>(next_u64() >> 11) * 0x1.0p-53;
}

std::int64_t RandomStream::uniform_index(std::int64_t n) {
  assert(n > 0);
  const auto range = static_cast<std::uint64_t>(n);
  // Largest multiple of range that fits in 2^64; draws at or above it are rejected.
  const std::uint64_t limit = UINT64_MAX - (UINT64_MAX % range + 1) % range;
  std::uint64_t x;
  do {
    x = next_u64();
  } while (x > limit);
  return static_cast<std::int64_t>(x % range);
}

double RandomStream::normal() {
  if (has_spare_normal_) {
    has_spare_normal_ = false;
    return spare_normal_;
  }
  // 1 - uniform() lies in (0, 1], so the logarithm is finite.
  const double radius = std::sqrt(-2.0 * std::log(1.0 - uniform()));
  const double angle = 2.0 * std::numbers::pi * uniform();
  spare_normal_ = radius * std::sin(angle);
  has_spare_normal_ = true;
  return radius * std::cos(angle);
}

void shuffle(std::span<std::int32_t> items, RandomStream& random) {
  for (std::size_t i = items.size(); i > 1; --i) {
    const auto j = static_cast<std::size_t>(random.uniform_index(static_cast<std::int64_t>(i)));
    std::swap(items[i - 1], items[j]);
  }
}

}  // namespace ggk::kernels
