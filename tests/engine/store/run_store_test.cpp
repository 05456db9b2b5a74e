// Where runs and the summary live in a results file: fit group names, the staged
// summary, discarded runs.

#include "engine/store/run_store.hpp"

#include <gtest/gtest.h>
#include <unistd.h>
#include <algorithm>

#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "engine/job/sweep.hpp"

namespace ggk::engine {
namespace {

namespace fs = std::filesystem;

TEST(FitGroupName, DistinctValuesGetDistinctNames) {
  JobSpec job;
  job.sweep.basis = {KernelType::ggk};
  job.sweep.kernels = {16};
  job.sweep.sigma = {10.0, 10.000001, 10.0000000000001, 2.5, 1e-6, 100000.0};
  job.sweep.solver = {kernels::LspiSolver::brm};
  job.sweep.lambda = {1e-6, 1.0000000000000002e-6};
  std::set<std::string> names;
  const std::vector<SweepPoint> points = expand_sweep(job);
  for (const SweepPoint& point : points) names.insert(fit_group_name(job, point));
  EXPECT_EQ(names.size(), points.size());
  EXPECT_TRUE(names.count("ggk/k_0016_sigma10.000001_brm_lambda1e-06")) << *names.begin();
  EXPECT_TRUE(names.count("ggk/k_0016_sigma2.5_brm_lambda1e-06"));
}

TEST(FitGroupName, DoesNotDependOnWhichAxesAreSwept) {
  // The same fit (16 kernels, sigma 2.5, BRM, lambda 1e-6) in a job sweeping
  // nothing but kernels and in one sweeping every axis gets one name.
  JobSpec narrow;
  narrow.sweep.basis = {KernelType::ggk};
  narrow.sweep.kernels = {16};
  narrow.sweep.sigma = {2.5};
  narrow.sweep.solver = {kernels::LspiSolver::brm};
  narrow.sweep.lambda = {1e-6};
  JobSpec wide = narrow;
  wide.sweep.basis = {KernelType::ogk, KernelType::ggk};
  wide.sweep.kernels = {4, 16};
  wide.sweep.sigma = {1.0, 2.5};
  wide.sweep.solver = {kernels::LspiSolver::lstdq, kernels::LspiSolver::brm};
  wide.sweep.lambda = {1e-3, 1e-6};
  const SweepPoint only = expand_sweep(narrow).front();
  const std::vector<SweepPoint> all = expand_sweep(wide);
  const auto same = std::find_if(all.begin(), all.end(), [&](const SweepPoint& p) {
    return p.basis == only.basis && p.kernels == only.kernels && p.sigma == only.sigma &&
           p.solver == only.solver && p.lambda == only.lambda;
  });
  ASSERT_NE(same, all.end());
  EXPECT_EQ(fit_group_name(narrow, only), "ggk/k_0016_sigma2.5_brm_lambda1e-06");
  EXPECT_EQ(fit_group_name(wide, *same), fit_group_name(narrow, only));
  EXPECT_EQ(fit_group_name(*same), fit_group_name(narrow, only));
  std::set<std::string> names;
  for (const SweepPoint& point : all) names.insert(fit_group_name(point));
  EXPECT_EQ(names.size(), all.size());
}

class RunStoreTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           ("ggk_run_store_test_" + std::to_string(::getpid()) + "_" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // A file of task "maze" with `runs` complete runs of one fit_metrics row each.
  Hdf5File file_with_runs(int runs) {
    Hdf5File file = Hdf5File::create(dir_ / "r.h5");
    const std::vector<TableColumn> columns = {{"run", ColumnType::kInt32, 0},
                                              {"value", ColumnType::kFloat64, 0}};
    for (int run = 0; run < runs; ++run) {
      const std::string group = run_group("maze", run);
      file.create_table(group + "/fit_metrics", columns);
      const std::vector<TableRow> rows = {{run, 0.5 * run}};
      file.append_rows(group + "/fit_metrics", rows);
      file.write_int64_attribute(group, "complete", 1);
    }
    return file;
  }

  fs::path dir_;
};

TEST_F(RunStoreTest, SummaryIsRewrittenWholeAndLeavesNoStaging) {
  Hdf5File file = file_with_runs(3);
  file.create_group(staging_group("maze", 7));  // what a finished job's writes leave
  EXPECT_EQ(write_summary(file, "maze", 3), 3);
  EXPECT_EQ(write_summary(file, "maze", 3), 3);  // replaces the old one
  EXPECT_EQ(file.read_table("/maze/summary").size(), 3u);
  EXPECT_FALSE(file.exists(kStagingRoot));
}

TEST_F(RunStoreTest, SummaryOfRunsWithFloatAndIntegerMetricColumnsTakesTheFirstRunsTypes) {
  // An older ggk wrote whole-number metrics as float64, this one as int64: a
  // resumed or merged file holding both makes one summary, exact values kept.
  for (const bool older_first : {true, false}) {
    const fs::path path = dir_ / (older_first ? "older_first.h5" : "newer_first.h5");
    Hdf5File file = Hdf5File::create(path);
    for (int run = 0; run < 2; ++run) {
      const bool older = (run == 0) == older_first;
      const std::string group = run_group("maze", run);
      file.create_table(
          group + "/fit_metrics",
          std::vector<TableColumn>{
              {"run", ColumnType::kInt32, 0},
              {"lspi_iterations", older ? ColumnType::kFloat64 : ColumnType::kInt64, 0}});
      std::vector<TableRow> rows(1, TableRow{run});
      if (older) {
        rows[0].emplace_back(7.0);
      } else {
        rows[0].emplace_back(std::int64_t{7});
      }
      file.append_rows(group + "/fit_metrics", rows);
      file.write_int64_attribute(group, "complete", 1);
    }
    ASSERT_EQ(write_summary(file, "maze", 2), 2);
    const auto columns = file.read_table_columns("/maze/summary");
    EXPECT_EQ(columns[1].type, older_first ? ColumnType::kFloat64 : ColumnType::kInt64);
    for (const TableRow& row : file.read_table("/maze/summary")) {
      if (older_first) {
        EXPECT_EQ(std::get<double>(row[1]), 7.0);
      } else {
        EXPECT_EQ(std::get<std::int64_t>(row[1]), 7);
      }
    }
  }
}

TEST_F(RunStoreTest, DiscardedRunIsGoneAndNotComplete) {
  Hdf5File file = file_with_runs(2);
  discard_run(file, "maze", 1);
  EXPECT_FALSE(run_is_complete(file, "maze", 1));
  EXPECT_TRUE(run_is_complete(file, "maze", 0));
  EXPECT_EQ(write_summary(file, "maze", 2), 1);
  EXPECT_FALSE(file.exists(kStagingRoot));
}

TEST_F(RunStoreTest, NamedArraysAreStoredAsTheirElementType) {
  JobSpec job;
  job.task = "maze";
  RunRecord record;
  record.run = 4;
  record.graph.num_nodes = 0;
  record.graph.indptr = {0};
  record.arrays = {
      {"som/quantization_error", {3}, {0.5, -1.0, 2.0}},  // float64 by default
      {"grid/state_of", {2, 2}, {0, 1, 2, -3}, ElementType::kInt32},
      {"start_states", {2}, {0, 4294967296.0}, ElementType::kInt64},
      {"graph/visited", {3}, {1, 0, 1}, ElementType::kUInt8},
  };
  static constexpr DatasetSpec kTyped[] = {
      {"som/quantization_error", "epoch", "", "a float64 array"},
      {"grid/state_of", "row,column", "", "an int32 matrix"},
      {"start_states", "start", "", "an int64 array"},
      {"graph/visited", "node", "", "a uint8 array"},
  };
  record.dataset_specs = {{"this test", kTyped}};
  {
    Hdf5File file = Hdf5File::create(dir_ / "typed.h5");
    write_run(file, job, record);
    EXPECT_FALSE(file.exists(kStagingRoot)) << "a committed run leaves no empty /.staging";
  }
  const Hdf5File file = Hdf5File::open_read_only(dir_ / "typed.h5");
  const std::string group = run_group("maze", 4);
  EXPECT_EQ(file.read_vector<double>(group + "/som/quantization_error"),
            (std::vector<double>{0.5, -1.0, 2.0}));
  EXPECT_EQ(file.read_matrix<std::int32_t>(group + "/grid/state_of").data,
            (std::vector<std::int32_t>{0, 1, 2, -3}));
  EXPECT_EQ(file.read_vector<std::int64_t>(group + "/start_states"),
            (std::vector<std::int64_t>{0, std::int64_t{1} << 32}));
  EXPECT_EQ(file.read_vector<std::uint8_t>(group + "/graph/visited"),
            (std::vector<std::uint8_t>{1, 0, 1}));
  // Reading as another type is refused: the stored type is the declared one.
  EXPECT_THROW(file.read_vector<double>(group + "/graph/visited"), std::runtime_error);

  // A value that is no integer of the type is a bug of the task, not rounded.
  Hdf5File other = Hdf5File::create(dir_ / "bad.h5");
  record.arrays = {{"graph/visited", {2}, {1, 0.5}, ElementType::kUInt8}};
  EXPECT_THROW(write_run(other, job, record), std::logic_error);
  record.arrays = {{"graph/visited", {1}, {256}, ElementType::kUInt8}};
  EXPECT_THROW(write_run(other, job, record), std::logic_error);
}

// A fit's warning (FitRecord::warning) is its attribute `warning`, left out
// when there is none (so that fits without one are stored as before).
TEST_F(RunStoreTest, AFitsWarningIsAnAttributeOnlyWhenThereIsOne) {
  JobSpec job;
  job.task = "maze";
  RunRecord record;
  record.run = 1;
  record.graph.num_nodes = 0;
  record.graph.indptr = {0};
  record.fits.resize(2);
  for (std::size_t i = 0; i < 2; ++i) {
    record.fits[i].point.basis = KernelType::pvf;
    record.fits[i].point.kernels = 3 + static_cast<std::int32_t>(i);
    record.fits[i].point.index = static_cast<std::int32_t>(i);
    record.fits[i].status = "converged";
  }
  record.fits[1].warning = "the basis is not determined by the graph";
  {
    Hdf5File file = Hdf5File::create(dir_ / "warned.h5");
    write_run(file, job, record);
  }
  const Hdf5File file = Hdf5File::open_read_only(dir_ / "warned.h5");
  const std::string fits = run_group("maze", 1) + "/fits/";
  EXPECT_FALSE(file.has_attribute(fits + fit_group_name(job, record.fits[0].point), "warning"));
  EXPECT_EQ(file.read_string_attribute(fits + fit_group_name(job, record.fits[1].point), "warning"),
            record.fits[1].warning);
}

TEST(IsScratch, NamesTheWritersScratchOnly) {
  EXPECT_TRUE(is_scratch(".staging"));
  EXPECT_TRUE(is_scratch(".staging_discarded_3"));
  EXPECT_FALSE(is_scratch("maze"));
  EXPECT_FALSE(is_scratch("staging"));
}

}  // namespace
}  // namespace ggk::engine
