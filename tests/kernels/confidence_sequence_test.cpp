// The empirical-Bernstein confidence sequence (kernels/confidence_sequence.hpp):
// its first steps by hand, its limits, and its time-uniform coverage: over many
// sequences of paired differences with mean 0, the share whose interval ever
// leaves out 0 (looking after every observation) stays below 1 - level.

#include "kernels/confidence_sequence.hpp"

#include <cmath>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

#include "kernels/random_stream.hpp"

namespace ggk::kernels {
namespace {

TEST(ConfidenceSequence, TheFirstStepIsTheFormulaByHand) {
  const std::vector<double> x = {1.0, 0.0};
  const ConfidenceSequence cs = confidence_sequence(x, -1.0, 1.0, 0.95);
  ASSERT_EQ(cs.lower.size(), 2u);
  // t = 1: y = 1, lambda = min(sqrt(2 log 40 / (1/4 * 1 * log 2)), 1/2) = 1/2,
  // v = 4 (1 - 1/2)^2 = 1, centre = y = 1, radius = (log 40 + psi(1/2)) / (1/2).
  const double psi = (-std::log(0.5) - 0.5) / 4.0;
  const double radius = (std::log(40.0) + psi) / 0.5;
  EXPECT_DOUBLE_EQ(cs.lower[0], -1.0 + 2.0 * std::max(0.0, 1.0 - radius));
  EXPECT_DOUBLE_EQ(cs.upper[0], 1.0);
  EXPECT_LE(cs.lower[1], cs.upper[1]);
}

TEST(ConfidenceSequence, NarrowsAroundAConstantAndNeverWidens) {
  const std::vector<double> x(400, 0.25);
  const ConfidenceSequence cs = confidence_sequence(x, -1.0, 1.0, 0.95);
  for (std::size_t t = 1; t < x.size(); ++t) {
    EXPECT_GE(cs.lower[t], cs.lower[t - 1]);
    EXPECT_LE(cs.upper[t], cs.upper[t - 1]);
    EXPECT_LE(cs.lower[t], 0.25);
    EXPECT_GE(cs.upper[t], 0.25);
  }
  EXPECT_LT(cs.upper.back() - cs.lower.back(), 0.2);
}

TEST(ConfidenceSequence, RefusesValuesOutsideTheBoundsAndBadLevels) {
  const std::vector<double> x = {0.5, 1.5};
  EXPECT_THROW(confidence_sequence(x, 0.0, 1.0, 0.95), std::invalid_argument);
  EXPECT_THROW(confidence_sequence({}, 1.0, 1.0, 0.95), std::invalid_argument);
  EXPECT_THROW(confidence_sequence({}, 0.0, 1.0, 1.0), std::invalid_argument);
  EXPECT_TRUE(confidence_sequence({}, 0.0, 1.0, 0.9).lower.empty());
}

// Paired differences of two Bernoulli(0.4) outcomes: values in {-1, 0, 1},
// mean 0. 400 sequences of 200 runs, every prefix looked at: the share whose
// interval ever misses 0 is at most 5 % (the guarantee; the method is
// conservative: it is near 0 here).
TEST(ConfidenceSequence, CoversTheMeanAtEveryLookAtOnce) {
  RandomStream random(2023, 0, 0);
  int misses = 0;
  constexpr int kSequences = 400;
  for (int s = 0; s < kSequences; ++s) {
    std::vector<double> x(200);
    for (double& d : x) {
      d = (random.uniform() < 0.4 ? 1.0 : 0.0) - (random.uniform() < 0.4 ? 1.0 : 0.0);
    }
    const ConfidenceSequence cs = confidence_sequence(x, -1.0, 1.0, 0.95);
    bool missed = false;
    for (std::size_t t = 0; t < x.size(); ++t) missed |= cs.lower[t] > 0.0 || cs.upper[t] < 0.0;
    misses += missed ? 1 : 0;
  }
  EXPECT_LE(misses, kSequences * 5 / 100);
}

}  // namespace
}  // namespace ggk::kernels

namespace ggk::kernels {
namespace {

// The asymptotic sequence at t = 4 of 1, 2, 3, 4 (level 0.95, horizon 10), by
// hand: mean 2.5, s = sqrt(5/3), rho^2 = (5.99146 + log 6.99146) / 10 =
// 0.793615, half = s sqrt(2 (4 rho^2 + 1) / (16 rho^2) log(sqrt(4 rho^2 + 1) /
// 0.05)) t_3 / z = 3.27407 (ggk_results.asymptotic_confidence_sequence:
// -0.7740679367299137, 5.774067936729914).
TEST(AsymptoticConfidenceSequence, MatchesTheFormulaByHand) {
  const std::vector<double> x = {1.0, 2.0, 3.0, 4.0};
  const ConfidenceSequence cs = asymptotic_confidence_sequence(x, 0.95, 10);
  ASSERT_EQ(cs.lower.size(), 4u);
  EXPECT_TRUE(std::isinf(cs.lower[0]) && cs.lower[0] < 0.0);
  EXPECT_TRUE(std::isinf(cs.upper[0]) && cs.upper[0] > 0.0);
  EXPECT_NEAR(cs.lower[3], -0.7740679367299137, 1e-9);
  EXPECT_NEAR(cs.upper[3], 5.774067936729914, 1e-9);
  // Equal values: a point; a wider level: a wider interval.
  const std::vector<double> same = {0.5, 0.5, 0.5};
  EXPECT_DOUBLE_EQ(asymptotic_confidence_sequence(same, 0.95, 10).lower[2], 0.5);
  EXPECT_LT(asymptotic_confidence_sequence(x, 0.999, 10).lower[3], cs.lower[3]);
  EXPECT_THROW(asymptotic_confidence_sequence(x, 1.0, 10), std::invalid_argument);
  EXPECT_THROW(asymptotic_confidence_sequence(x, 0.95, 0), std::invalid_argument);
  const std::vector<double> bad = {1.0, std::nan("")};
  EXPECT_THROW(asymptotic_confidence_sequence(bad, 0.95, 10), std::invalid_argument);
}

}  // namespace
}  // namespace ggk::kernels
