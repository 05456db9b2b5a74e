#include "engine/store/results_info.hpp"

#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "engine/hdf5/hdf5_file.hpp"
#include "engine/run/job_runner.hpp"
#include "engine/tasks/task_list.hpp"
#include "support/determinism_job.hpp"

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

// A per-run fraction of episodes (the Khepera's collision fraction) is a mean
// over runs, never Wilson: four runs without a collision give [0, 0], where
// Wilson, treating each run as one trial, gave [0, 49 %]. A 0/1 outcome per run
// keeps Wilson.
TEST(ConfidenceIntervals, AFractionPerRunIsAMeanAndAnOutcomePerRunIsWilson) {
  const std::vector<double> zeros(4, 0.0);
  const Interval fraction = metric_interval(zeros, MetricKind::kFraction);
  EXPECT_EQ(fraction.low, 0.0);
  EXPECT_EQ(fraction.high, 0.0);
  const Interval outcome = metric_interval(zeros, MetricKind::kRate);
  EXPECT_NEAR(outcome.high, 0.4899, 1e-4);  // scipy binomtest(0, 4).proportion_ci("wilson")
  const std::vector<double> shares = {0.1, 0.3, 0.0, 0.2};
  const Interval clipped = metric_interval(shares, MetricKind::kFraction);
  EXPECT_NEAR(clipped.estimate, 0.15, 1e-12);
  EXPECT_EQ(clipped.low, 0.0);  // t's lower bound, -0.055, clipped
  EXPECT_NEAR(clipped.high, 0.15 + 3.1824 * std::sqrt(0.0166667 / 4), 1e-3);
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

// A file may hold any text in an attribute: ggk info prints each on one line
// of at most 300 characters with its size (an 8 MB `git` was printed whole).
class ResultsInfoFileTest : public test_support::JobRunnerTest {};

TEST_F(ResultsInfoFileTest, AHugeAttributeIsCutToALine) {
  const JobSpec job = load_job("job.toml", test_support::determinism_job(dir_ / "out.h5"));
  run_job(job, test_support::options_for(dir_ / "out.h5"));
  {
    Hdf5File file = Hdf5File::open_read_write(dir_ / "out.h5");
    file.remove_attribute("/", "git");
    file.write_string_attribute("/", "git", std::string(8'000'000, 'x') + "\nsecond line");
    file.flush();
  }
  std::ostringstream out;
  print_results_info(dir_ / "out.h5", out, InfoFormat::kText, metric_kind);
  EXPECT_LT(out.str().size(), 20'000u);
  EXPECT_NE(out.str().find("... (8000012 bytes))"), std::string::npos) << out.str().substr(0, 600);
  EXPECT_NE(out.str().find("runs:     3 of 3 complete"), std::string::npos);
}

}  // namespace
}  // namespace ggk::engine
