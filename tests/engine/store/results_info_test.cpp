#include "engine/store/results_info.hpp"

#include <cmath>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "engine/hdf5/hdf5_file.hpp"
#include "engine/job/usage_error.hpp"
#include "engine/run/job_runner.hpp"
#include "engine/store/metric_specs_table.hpp"
#include "engine/store/results_contents.hpp"
#include "engine/store/run_store.hpp"
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
  const MetricSpec share = fraction_metric("collision_fraction", "");
  const Interval fraction = metric_interval(zeros, share);
  EXPECT_EQ(fraction.low, 0.0);
  EXPECT_EQ(fraction.high, 0.0);
  const Interval outcome = metric_interval(zeros, indicator_metric("success_from_A", ""));
  EXPECT_NEAR(outcome.high, 0.4899, 1e-4);  // scipy binomtest(0, 4).proportion_ci("wilson")
  const std::vector<double> shares = {0.1, 0.3, 0.0, 0.2};
  const Interval clipped = metric_interval(shares, share);
  EXPECT_NEAR(clipped.estimate, 0.15, 1e-12);
  EXPECT_EQ(clipped.low, 0.0);  // t's lower bound, -0.055, clipped
  EXPECT_NEAR(clipped.high, 0.15 + 3.1824 * std::sqrt(0.0166667 / 4), 1e-3);
}

// A bounded mean (steps of a 100-step cap) gets an interval inside its range:
// Student's t alone gives [-38.2, 138.2] for these values ("mean_steps 136.2
// [-39.6, 311.9]" of at most 150 was the report), intersected [0, 100]. An
// unbounded mean keeps Student's t.
TEST(ConfidenceIntervals, ABoundedMeanGetsAnIntervalInsideItsRange) {
  const std::vector<double> steps = {1.0, 99.0, 3.0, 97.0};
  const Interval bounded = metric_interval(steps, mean_metric("mean_steps", "steps", "", 0, 100));
  EXPECT_EQ(bounded.estimate, 50.0);
  EXPECT_EQ(bounded.low, 0.0);
  EXPECT_EQ(bounded.high, 100.0);
  const Interval free = metric_interval(steps, mean_metric("mean_return", "1", ""));
  EXPECT_NEAR(free.low, 50.0 - 3.182446 * std::sqrt(3073.333333 / 4.0), 1e-3);
  EXPECT_LT(free.low, -38.0);
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
  print_results_info(dir_ / "out.h5", out, InfoFormat::kText);
  EXPECT_LT(out.str().size(), 20'000u);
  EXPECT_NE(out.str().find("... (8000012 bytes))"), std::string::npos) << out.str().substr(0, 600);
  EXPECT_NE(out.str().find("runs:     3 of 3 complete"), std::string::npos);
}

// The file declares its metrics (metric_specs beside each run's fit_metrics and
// beside the summary); info prints them as a legend and bounds the intervals by
// them. A file without them (an older ggk's) is read by the legacy kinds, and
// info says so.
TEST_F(ResultsInfoFileTest, TheLegendComesFromTheFilesDeclarations) {
  const JobSpec job = load_job("job.toml", test_support::determinism_job(dir_ / "out.h5"));
  run_job(job, test_support::options_for(dir_ / "out.h5"));
  {
    const Hdf5File file = Hdf5File::open_read_only(dir_ / "out.h5");
    const std::optional<std::vector<MetricSpec>> summary =
        read_metric_specs(file, "/" + job.task + "/" + kMetricSpecsTable);
    ASSERT_TRUE(summary.has_value());
    EXPECT_EQ(summary->back().name, "fit_seconds");
    const MetricSpec* success = find_metric_spec(*summary, "success_rate");
    ASSERT_NE(success, nullptr);
    EXPECT_EQ(success->kind, MetricKind::kFraction);
    EXPECT_EQ(success->high, 1.0);
    const ResultsContents contents = read_contents(file);
    EXPECT_TRUE(contents.metrics_declared);
    ASSERT_EQ(contents.metric_specs.size(), contents.metric_names.size());
    for (std::size_t m = 0; m < contents.metric_names.size(); ++m) {
      EXPECT_EQ(contents.metric_specs[m].name, contents.metric_names[m]);
      EXPECT_FALSE(contents.metric_specs[m].meaning.empty()) << contents.metric_names[m];
    }
  }
  std::ostringstream out;
  print_results_info(dir_ / "out.h5", out, InfoFormat::kText);
  EXPECT_NE(out.str().find("metrics:\n  success_rate "), std::string::npos) << out.str();
  EXPECT_NE(out.str().find("[steps]"), std::string::npos) << out.str();
  {
    Hdf5File file = Hdf5File::open_read_write(dir_ / "out.h5");
    file.remove("/" + job.task + "/" + kMetricSpecsTable);
    for (std::int32_t run = 0; run < job.runs; ++run) {
      file.remove(run_group(job.task, run) + "/" + kMetricSpecsTable);
    }
    file.flush();
  }
  std::ostringstream legacy;
  print_results_info(dir_ / "out.h5", legacy, InfoFormat::kText);
  EXPECT_NE(legacy.str().find("the file declares none"), std::string::npos) << legacy.str();
  const Hdf5File file = Hdf5File::open_read_only(dir_ / "out.h5");
  const ResultsContents contents = read_contents(file);
  EXPECT_FALSE(contents.metrics_declared);
  EXPECT_EQ(declared_kind(contents.metric_specs, "success_rate"), MetricKind::kFraction);
}

TEST(MetricSpecsTable, ReadsBackWhatItWritesAndRefusesAnUnknownKind) {
  Hdf5File file = Hdf5File::create_in_memory("specs");
  const std::vector<MetricSpec> specs = {
      tested(fraction_metric("collision_fraction", "share of the episodes")),
      indicator_metric("success_from_A", "1 when A reaches a goal"),
      mean_metric("mean_return", "1", "summed rewards", -2.0, 300.0), fit_seconds_spec()};
  write_metric_specs(file, "/t/metric_specs", specs);
  const auto back = read_metric_specs(file, "/t/metric_specs");
  ASSERT_TRUE(back.has_value());
  ASSERT_EQ(back->size(), specs.size());
  for (std::size_t m = 0; m < specs.size(); ++m) {
    EXPECT_EQ((*back)[m].name, specs[m].name);
    EXPECT_EQ((*back)[m].kind, specs[m].kind);
    EXPECT_EQ((*back)[m].unit, specs[m].unit);
    EXPECT_EQ((*back)[m].meaning, specs[m].meaning);
    EXPECT_EQ((*back)[m].low, specs[m].low);
    EXPECT_EQ((*back)[m].high, specs[m].high);
  }
  EXPECT_FALSE(read_metric_specs(file, "/t/none").has_value());
  file.create_table("/t/bad", std::vector<TableColumn>{{"name", ColumnType::kString},
                                                       {"kind", ColumnType::kString},
                                                       {"unit", ColumnType::kString},
                                                       {"meaning", ColumnType::kString},
                                                       {"low", ColumnType::kFloat64},
                                                       {"high", ColumnType::kFloat64}});
  file.append_rows("/t/bad", std::vector<TableRow>{{std::string("m"), std::string("rate"),
                                                    std::string(""), std::string(""), 0.0, 1.0}});
  EXPECT_THROW(read_metric_specs(file, "/t/bad"), std::runtime_error);
  // A study's configurations: each range the smallest holding both.
  const std::vector<MetricSpec> short_cap = {mean_metric("mean_steps", "steps", "", 0, 50)};
  const std::vector<MetricSpec> long_cap = {mean_metric("mean_steps", "steps", "", 0, 100),
                                            fit_seconds_spec()};
  const std::vector<MetricSpec> both = united_metric_specs(short_cap, long_cap);
  ASSERT_EQ(both.size(), 2u);
  EXPECT_EQ(both[0].high, 100.0);
  EXPECT_EQ(both[1].name, "fit_seconds");
}

}  // namespace
}  // namespace ggk::engine
