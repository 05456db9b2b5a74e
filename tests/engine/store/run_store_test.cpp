// Where runs and the summary live in a results file: fit group names, the staged
// summary, discarded runs.

#include "engine/store/run_store.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

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
  EXPECT_TRUE(names.count("ggk/k_0016_sigma10.000001_lambda1e-06")) << *names.begin();
  EXPECT_TRUE(names.count("ggk/k_0016_sigma2.5_lambda1e-06"));
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

TEST_F(RunStoreTest, DiscardedRunIsGoneAndNotComplete) {
  Hdf5File file = file_with_runs(2);
  discard_run(file, "maze", 1);
  EXPECT_FALSE(run_is_complete(file, "maze", 1));
  EXPECT_TRUE(run_is_complete(file, "maze", 0));
  EXPECT_EQ(write_summary(file, "maze", 2), 1);
  EXPECT_FALSE(file.exists(kStagingRoot));
}

TEST(IsScratch, NamesTheWritersScratchOnly) {
  EXPECT_TRUE(is_scratch(".staging"));
  EXPECT_TRUE(is_scratch(".staging_discarded_3"));
  EXPECT_FALSE(is_scratch("maze"));
  EXPECT_FALSE(is_scratch("staging"));
}

}  // namespace
}  // namespace ggk::engine
