#pragma once
// Counter-based random numbers (Philox4x32-10, Random123).
//
// A stream is keyed by (seed, stream, purpose): the same triple gives the same
// sequence on every machine, standard library and thread count, and distinct
// triples give independent sequences. The engine uses stream = run index and
// purpose = what the numbers are for (sampling, centres, evaluation, ...), so a
// run's result never depends on which thread or rank computed it.
//
// Samplers are written out here (no std::*_distribution, whose output differs
// between standard libraries).
//
// Thread-safety: none; one stream per task. Copying a stream copies its position.

#include <cstdint>
#include <span>

namespace ggk::kernels {

class RandomStream {
 public:
  RandomStream(std::uint64_t seed, std::uint32_t stream, std::uint32_t purpose);

  // 64 uniformly distributed bits.
  std::uint64_t next_u64();
  // Uniform on [0, 1) with 53 random bits.
  double uniform();
  // Uniform on [lo, hi).
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  // Uniform integer in [0, n), exactly unbiased (rejection sampling); n > 0.
  std::int64_t uniform_index(std::int64_t n);
  // Standard normal (Box-Muller).
  double normal();
  // True with probability p.
  bool bernoulli(double p) { return uniform() < p; }

 private:
  void refill();

  std::uint32_t key_[2];
  std::uint32_t counter_[4];
  std::uint64_t block_[2] = {0, 0};
  int available_ = 0;  // unread 64-bit words in block_
  double spare_normal_ = 0.0;
  bool has_spare_normal_ = false;
};

// Uniformly random permutation in place (Fisher-Yates, from the back).
void shuffle(std::span<std::int32_t> items, RandomStream& random);

}  // namespace ggk::kernels
