#include "engine/store/results_info.hpp"

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

namespace ggk::engine {
namespace {

TEST(ConfidenceIntervals, StudentTMatchesScipy) {
  // scipy.stats.t.ppf(0.975, dof)
  EXPECT_NEAR(student_t_975(1), 12.706205, 1e-6);
  EXPECT_NEAR(student_t_975(29), 2.045230, 1e-6);
  EXPECT_NEAR(student_t_975(31), 2.0395134463964077, 1e-5);
  EXPECT_NEAR(student_t_975(40), 2.0210753829953374, 1e-5);
  EXPECT_NEAR(student_t_975(100), 1.9839715184496334, 1e-6);
  EXPECT_NEAR(student_t_975(1000), 1.9623390808264074, 1e-6);
  const std::vector<double> values = {1.0, 2.0, 3.0, 4.0, std::nan("")};
  const Interval ci = mean_interval(values);
  EXPECT_DOUBLE_EQ(ci.estimate, 2.5);
  // sd = 1.2910, n = 4: half-width t(3) sd / 2 = 2.054
  EXPECT_NEAR(ci.high - ci.estimate, 3.182446 * std::sqrt(5.0 / 3.0) / 2.0, 1e-5);
}

TEST(ConfidenceIntervals, WilsonStaysInsideZeroOneAndIsWideAtTheEnds) {
  const Interval none = wilson_interval(0, 30);
  EXPECT_EQ(none.estimate, 0.0);
  EXPECT_EQ(none.low, 0.0);
  EXPECT_NEAR(none.high, 0.11351, 1e-4);  // statsmodels proportion_confint(0, 30, method="wilson")
  const Interval all = wilson_interval(30, 30);
  EXPECT_NEAR(all.low, 1.0 - 0.11351, 1e-4);
  EXPECT_EQ(all.high, 1.0);
  const Interval some = wilson_interval(20, 30);
  EXPECT_NEAR(some.low, 0.48779, 1e-4);
  EXPECT_NEAR(some.high, 0.80774, 1e-4);
}

}  // namespace
}  // namespace ggk::engine
