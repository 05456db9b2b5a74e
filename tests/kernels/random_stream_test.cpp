#include "kernels/random_stream.hpp"

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

namespace ggk::kernels {
namespace {

TEST(RandomStream, MatchesPhiloxKnownAnswer) {
  // Random123's known-answer test for philox4x32-10 with zero counter and key:
  // {0x6627e8d5, 0xe169c58d, 0xbc57ac4c, 0x9b00dbd8}.
  RandomStream stream(0, 0, 0);
  EXPECT_EQ(stream.next_u64(), 0xe169c58d6627e8d5ull);
  EXPECT_EQ(stream.next_u64(), 0x9b00dbd8bc57ac4cull);
}

TEST(RandomStream, SameKeyGivesSameSequenceAndKeysAreIndependent) {
  RandomStream a(42, 3, 7), b(42, 3, 7), other_run(42, 4, 7), other_purpose(42, 3, 8),
      other_seed(43, 3, 7);
  int equal_run = 0, equal_purpose = 0, equal_seed = 0;
  for (int i = 0; i < 1000; ++i) {
    const std::uint64_t x = a.next_u64();
    ASSERT_EQ(x, b.next_u64());
    equal_run += x == other_run.next_u64();
    equal_purpose += x == other_purpose.next_u64();
    equal_seed += x == other_seed.next_u64();
  }
  EXPECT_EQ(equal_run, 0);
  EXPECT_EQ(equal_purpose, 0);
  EXPECT_EQ(equal_seed, 0);
}

TEST(RandomStream, UniformHasTheRightMoments) {
  RandomStream stream(1, 0, 0);
  const int n = 200000;
  double sum = 0, sum_sq = 0;
  for (int i = 0; i < n; ++i) {
    const double u = stream.uniform();
    ASSERT_GE(u, 0.0);
    ASSERT_LT(u, 1.0);
    sum += u;
    sum_sq += u * u;
  }
  const double mean = sum / n;
  EXPECT_NEAR(mean, 0.5, 5 * std::sqrt(1.0 / 12 / n));
  EXPECT_NEAR(sum_sq / n - mean * mean, 1.0 / 12, 0.002);
}

TEST(RandomStream, UniformIndexCoversRangeEvenly) {
  RandomStream stream(2, 0, 0);
  const int buckets = 7, n = 70000;
  std::vector<int> counts(buckets, 0);
  for (int i = 0; i < n; ++i) {
    const auto k = stream.uniform_index(buckets);
    ASSERT_GE(k, 0);
    ASSERT_LT(k, buckets);
    ++counts[static_cast<std::size_t>(k)];
  }
  // Chi-square with 6 degrees of freedom; 22.46 is the 0.999 quantile.
  double chi2 = 0;
  for (int c : counts) chi2 += (c - n / buckets) * (c - n / buckets) / double(n / buckets);
  EXPECT_LT(chi2, 22.46);
  EXPECT_EQ(stream.uniform_index(1), 0);
}

TEST(RandomStream, NormalHasTheRightMoments) {
  RandomStream stream(3, 0, 0);
  const int n = 200000;
  double sum = 0, sum_sq = 0;
  for (int i = 0; i < n; ++i) {
    const double z = stream.normal();
    sum += z;
    sum_sq += z * z;
  }
  EXPECT_NEAR(sum / n, 0.0, 5 / std::sqrt(double(n)));
  EXPECT_NEAR(sum_sq / n, 1.0, 0.02);
}

}  // namespace
}  // namespace ggk::kernels
