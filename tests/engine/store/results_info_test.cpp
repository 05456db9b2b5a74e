#include "engine/store/results_info.hpp"

#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "engine/hdf5/hdf5_file.hpp"
#include "engine/job/usage_error.hpp"
#include "engine/run/job_runner.hpp"
#include "engine/tasks/task_list.hpp"
#include "support/determinism_job.hpp"

namespace ggk::engine {
namespace {

TEST(ConfidenceIntervals, StudentTMatchesScipy) {
  // The exact quantile (mpmath, 30 digits: tan(0.475 pi) for one degree of
  // freedom) to double precision, Boost.Math's; a table to 6 decimals and an
  // expansion beyond 30 were 1e-6 off. scipy.stats.t.ppf(0.975, dof) is itself
  // up to 7e-9 off (12.706204736432095 at 1, 2.0210753829953374 at 40).
  EXPECT_NEAR(student_t_975(1), 12.7062047361747046, 1e-13);
  EXPECT_NEAR(student_t_975(29), 2.04522964213270430, 1e-14);
  EXPECT_NEAR(student_t_975(31), 2.03951344639640849, 1e-14);
  EXPECT_NEAR(student_t_975(40), 2.02107539030627342, 1e-14);
  EXPECT_NEAR(student_t_975(100), 1.98397151852355229, 1e-14);
  EXPECT_NEAR(student_t_975(1000), 1.96233908082640848, 1e-14);
  EXPECT_TRUE(std::isnan(student_t_975(0)));
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

// python/ggk_results/intervals.py's paired_t_ci and newcombe_paired_ci on the
// same pairs (the numbers `ggk info --paired` and paired() must share).
TEST(ConfidenceIntervals, PairedIntervalsMatchPython) {
  const std::vector<double> x = {0.5, 0.7, 0.2, 0.9}, y = {0.1, 0.6, 0.3, 0.2};
  const Interval t = paired_t_interval(x, y);
  EXPECT_NEAR(t.estimate, 0.275, 1e-15);
  EXPECT_NEAR(t.low, -0.28192810342474595, 1e-9);  // scipy's t quantile: 1e-10 off
  EXPECT_NEAR(t.high, 0.831928103424746, 1e-9);
  const std::vector<double> a = {1, 1, 0, 1, 0, 1, 1, 0, 1, 1}, b = {0, 1, 0, 0, 0, 1, 0, 0, 1, 0};
  const Interval n = newcombe_paired_interval(a, b);
  EXPECT_NEAR(n.estimate, 0.4, 1e-15);
  EXPECT_NEAR(n.low, 0.014175050601760941, 1e-12);
  EXPECT_NEAR(n.high, 0.6445698550613561, 1e-12);
  const std::vector<double> ones(4, 1.0);  // no pair differs: not of zero width
  const Interval same = newcombe_paired_interval(ones, ones);
  EXPECT_EQ(same.estimate, 0.0);
  EXPECT_NEAR(same.low, -0.4898908364545973, 1e-12);
  EXPECT_NEAR(same.high, 0.4898908364545973, 1e-12);
  const std::vector<double> c = {0, 1, 0, 1, 1}, d = {1, 1, 0, 0, 1};
  EXPECT_NEAR(newcombe_paired_interval(c, d).high, 0.4648683508092225, 1e-12);
}

TEST(ConfidenceIntervals, PairedAndColumnsOptionsAreParsedOrNamed) {
  const PairedComparison p = parse_paired_option("basis=ggk,ogk");
  EXPECT_EQ(p.axis, "basis");
  EXPECT_EQ(p.a, "ggk");
  EXPECT_EQ(p.b, "ogk");
  for (const char* bad :
       {"basis", "basis=ggk", "=ggk,ogk", "basis=,ogk", "basis=ggk,", "b=x,y,z"}) {
    EXPECT_THROW(parse_paired_option(bad), UsageError) << bad;
  }
  EXPECT_EQ(info_column_list("a,b,c"), (std::vector<std::string>{"a", "b", "c"}));
  EXPECT_TRUE(info_column_list("").empty());
  EXPECT_THROW(info_column_list("a,,b"), UsageError);
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
