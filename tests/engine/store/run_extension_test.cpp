// Growing a stored run by the fits of new sweep points: against the run written
// whole with every point, in HDF5 files of a maze job (jobs/ci.toml).

#include "engine/store/run_extension.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <variant>
#include <vector>

#include "engine/job/job_file.hpp"
#include "engine/store/run_digest.hpp"
#include "engine/store/run_store.hpp"
#include "engine/tasks/task_list.hpp"
#include "support/files.hpp"

namespace ggk::engine {
namespace {

namespace fs = std::filesystem;

JobSpec ci_job() {
  const char* source_dir = std::getenv("GGK_SOURCE_DIR");
  if (source_dir == nullptr) throw std::runtime_error("ctest sets GGK_SOURCE_DIR");
  JobLoadOptions options;
  options.check_output = false;
  return load_job_file(fs::path(source_dir) / "jobs" / "ci.toml", task_tables(), options);
}

RunRecord compute(const JobSpec& job, const std::vector<SweepPoint>& points) {
  const TaskDefinition* task = find_task(job.task);
  RunRecord record = task->compute_run(job, 0, points);
  record.dataset_specs = task->datasets;
  return record;
}

Hdf5File new_file(const fs::path& path, const JobSpec& job) {
  Hdf5File file = Hdf5File::create(path, Hdf5File::CreateMode::kFailIfExists);
  file.create_group("/" + job.task);
  return file;
}

// The fit_metrics rows without their wall-clock column, NaN (a PVF fit's
// kernel_gap) as a text so that rows compare equal.
std::vector<TableRow> rows_without_time(const Hdf5File& file, const std::string& table) {
  std::vector<TableRow> rows = file.read_table(table);
  for (TableRow& row : rows) {
    row.pop_back();  // fit_seconds, the last column
    for (TableValue& value : row) {
      if (const double* number = std::get_if<double>(&value); number && std::isnan(*number)) {
        value = std::string("NaN");
      }
    }
  }
  return rows;
}

class RunExtension : public testing::Test {
 protected:
  void SetUp() override {
    job_ = ci_job();
    all_ = expand_sweep(job_);
    // The job before it grew: its smallest and largest kernel counts, numbered
    // in its own order; the grown job adds the counts between.
    const std::int32_t low = job_.sweep.kernels.front(), high = job_.sweep.kernels.back();
    for (const SweepPoint& point : all_) {
      if (point.kernels == low || point.kernels == high) {
        SweepPoint old = point;
        old.index = static_cast<std::int32_t>(old_.size());
        old_.push_back(old);
      } else {
        new_.push_back(point);
      }
    }
    ASSERT_FALSE(new_.empty());
    ASSERT_FALSE(old_.empty());
  }

  JobSpec job_;
  std::vector<SweepPoint> all_, old_, new_;
  test_support::ScratchDir scratch_{"ggk-extension"};
};

TEST_F(RunExtension, AGrownRunIsTheRunWrittenWithEveryPoint) {
  const std::string group = run_group(job_.task, 0);
  Hdf5File whole = new_file(scratch_.path() / "whole.h5", job_);
  write_run(whole, job_, compute(job_, all_));

  Hdf5File grown = new_file(scratch_.path() / "grown.h5", job_);
  write_run(grown, job_, compute(job_, old_));
  const std::vector<std::int32_t> lacking = lacking_points(grown, job_.task, 0, all_);
  std::vector<std::int32_t> expected;
  for (const SweepPoint& point : new_) expected.push_back(point.index);
  EXPECT_EQ(lacking, expected);
  RunRecord extension = compute(job_, new_);
  extension.extension = true;
  extend_run(grown, job_, extension, all_);

  EXPECT_TRUE(lacking_points(grown, job_.task, 0, all_).empty());
  EXPECT_TRUE(run_is_complete(grown, job_.task, 0));
  EXPECT_FALSE(grown.exists(kStagingRoot));
  // The digest covers every name, attribute (wall clock aside) and shape.
  EXPECT_EQ(grown.read_int64_attribute(group, kRunDigestAttribute),
            whole.read_int64_attribute(group, kRunDigestAttribute));
  EXPECT_EQ(static_cast<std::int64_t>(run_digest(grown, group)),
            grown.read_int64_attribute(group, kRunDigestAttribute));
  EXPECT_EQ(rows_without_time(grown, group + "/fit_metrics"),
            rows_without_time(whole, group + "/fit_metrics"));
  for (const SweepPoint& point : all_) {
    const std::string fit = group + "/fits/" + fit_group_name(point);
    SCOPED_TRACE(fit);
    EXPECT_EQ(grown.read_int64_attribute(fit, "sweep_point"), point.index);
    EXPECT_EQ(grown.read_vector<double>(fit + "/weights"),
              whole.read_vector<double>(fit + "/weights"));
    EXPECT_EQ(grown.read_vector<std::int32_t>(fit + "/policy"),
              whole.read_vector<std::int32_t>(fit + "/policy"));
  }
}

TEST_F(RunExtension, AStoredFitThatIsNoPointOfTheJobIsRefused) {
  Hdf5File grown = new_file(scratch_.path() / "grown.h5", job_);
  write_run(grown, job_, compute(job_, old_));
  // The job without the first old point: the run holds a fit the job lacks.
  std::vector<SweepPoint> fewer;
  for (const SweepPoint& point : all_) {
    if (fit_group_name(point) != fit_group_name(old_.front())) fewer.push_back(point);
  }
  try {
    lacking_points(grown, job_.task, 0, fewer);
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("holds the fit " + fit_group_name(old_.front()) +
                                         ", which is no sweep point of the job"),
              std::string::npos)
        << e.what();
  }
  RunRecord extension = compute(job_, new_);
  extension.extension = true;
  EXPECT_THROW(extend_run(grown, job_, extension, fewer), std::runtime_error);
  // The stored run is as it was: complete, its fits all there.
  EXPECT_TRUE(run_is_complete(grown, job_.task, 0));
  EXPECT_EQ(lacking_points(grown, job_.task, 0, all_).size(), new_.size());
}

}  // namespace
}  // namespace ggk::engine
