// The axes, units and descriptions of a run's datasets: every dataset the writer
// makes is described, a dataset missing from the schema is refused, and
// results/README.md's table is the schema's.

#include "engine/store/dataset_schema.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include "engine/job/sweep.hpp"
#include "engine/store/run_store.hpp"

namespace ggk::engine {
namespace {

namespace fs = std::filesystem;

constexpr const char* kBegin =
    "<!-- dataset schema: generated from engine/store/dataset_schema.cpp -->";
constexpr const char* kEnd = "<!-- end of dataset schema -->";

TEST(DatasetSchema, FindsRunAndFitDatasets) {
  ASSERT_NE(dataset_schema("samples/actions"), nullptr);
  EXPECT_EQ(dataset_schema("samples/actions")->dims, "sample");
  EXPECT_EQ(dataset_schema("graph/nodes")->dims, "node,observation_dim");
  const std::string fit = "fits/ggk/k_0016_sigma5_brm_lambda1e-06/";
  EXPECT_EQ(dataset_schema(fit + "history/weights")->dims, "iteration,coefficient");
  EXPECT_EQ(dataset_schema(fit + "history/success_rate")->dims, "iteration");  // history/*
  EXPECT_EQ(dataset_schema(fit + "steps_to_goal")->dims, "start");
  EXPECT_EQ(dataset_schema(fit + "trajectory_A")->dims, "step");
  // A task's own entry first (the Khepera's poses), else every task's.
  EXPECT_EQ(dataset_schema(fit + "evaluation/trajectory_3", "khepera")->dims, "step,pose");
  EXPECT_EQ(dataset_schema(fit + "evaluation/trajectory_3", "pendulum")->dims, "step,state_field");
  EXPECT_EQ(dataset_schema(fit + "evaluation/trajectory_3")->dims, "step,state_field");
  EXPECT_EQ(dataset_schema("som/prototypes", "khepera")->units, "IR reading");
  EXPECT_EQ(dataset_schema("samples/actions", "khepera")->dims, "sample");
  EXPECT_EQ(dataset_schema("steps_to_goal"), nullptr);  // a fit's, not a run's
  EXPECT_EQ(dataset_schema("fit:policy"), nullptr);
  EXPECT_EQ(dataset_schema("no_such_array"), nullptr);
}

class DescribedRunTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           ("ggk_dataset_schema_test_" + std::to_string(::getpid()) + "_" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    job_.task = "maze";
    job_.sweep.basis = {KernelType::ggk};
    job_.sweep.kernels = {2};
    job_.sweep.sigma = {5.0};
    job_.sweep.solver = {kernels::LspiSolver::brm};
    job_.sweep.lambda = {1e-6};
    record_.run = 0;
    record_.samples.observations = kernels::RowMatrixXd::Zero(3, 2);
    record_.samples.next_observations = kernels::RowMatrixXd::Zero(3, 2);
    record_.samples.actions = {0, 1, 3};
    record_.samples.rewards = {0.0, 0.0, 1.0};
    record_.samples.terminals = {0, 0, 1};
    record_.graph.num_nodes = 2;
    record_.graph.indptr = {0, 1, 2};
    record_.graph.indices = {1, 0};
    record_.graph.weights = {1.0, 1.0};
    record_.node_states = kernels::RowMatrixXd::Zero(2, 2);
    record_.action_names = {"up", "down", "left", "right"};
    record_.arrays = {{"start_states", {1}, {0}, ElementType::kInt32},
                      {"robot/radius", {1}, {2.6}}};  // shape (1,): one axis
    FitRecord fit;
    fit.point = expand_sweep(job_).front();
    fit.status = "converged";
    fit.centers = {0, 1};
    fit.lspi.weights = Eigen::VectorXd::Zero(8);
    fit.lspi.policy = {0, 2};
    fit.lspi.history.resize(2);
    fit.metrics = {{"success_rate", 1.0}};
    fit.arrays = {{"steps_to_goal", {1}, {3}, ElementType::kInt32},
                  {"history/success_rate", {2}, {0.0, 1.0}}};
    record_.fits = {fit};
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path dir_;
  JobSpec job_;
  RunRecord record_;
};

TEST_F(DescribedRunTest, EveryDatasetNamesItsAxesUnitsAndMeaning) {
  {
    Hdf5File file = Hdf5File::create(dir_ / "r.h5");
    write_run(file, job_, record_);
    write_summary(file, job_);
  }
  const Hdf5File file = Hdf5File::open_read_only(dir_ / "r.h5");
  int datasets = 0;
  std::function<void(const std::string&)> check = [&](const std::string& path) {
    if (file.object_kind(path) == Hdf5File::ObjectKind::kGroup) {
      for (const std::string& member : file.member_names(path)) check(path + "/" + member);
      return;
    }
    ++datasets;
    ASSERT_TRUE(file.has_attribute(path, "dims")) << path;
    ASSERT_TRUE(file.has_attribute(path, "units")) << path;
    ASSERT_TRUE(file.has_attribute(path, "description")) << path;
    // One axis name per dimension; "scalar" only for a dataset of no dimension.
    const std::string dims = file.read_string_attribute(path, "dims");
    const std::size_t commas = static_cast<std::size_t>(std::count(dims.begin(), dims.end(), ','));
    EXPECT_EQ(dims == "scalar" ? 0 : commas + 1, file.dataset_shape(path).size())
        << path << ": " << dims;
    EXPECT_FALSE(file.read_string_attribute(path, "description").empty()) << path;
  };
  check("/maze");
  EXPECT_GE(datasets, 20);
  const std::string fit = "/maze/run_000/fits/ggk/k_0002_sigma5_brm_lambda1e-06";
  EXPECT_EQ(file.read_string_attribute(fit + "/weights", "dims"), "coefficient");
  EXPECT_EQ(file.read_string_attribute(fit + "/steps_to_goal", "dims"), "start");
  EXPECT_EQ(file.read_string_attribute(fit + "/history/success_rate", "dims"), "iteration");
  EXPECT_EQ(file.read_string_attribute("/maze/summary", "dims"), "row");
  EXPECT_EQ(file.read_string_attribute("/maze/run_000/robot/radius", "dims"), "value");
  EXPECT_EQ(file.read_strings("/maze/run_000/action_names"),
            (std::vector<std::string>{"up", "down", "left", "right"}));
}

TEST_F(DescribedRunTest, ADatasetOutsideTheSchemaIsRefusedNamingIt) {
  record_.fits.front().arrays.push_back({"surprise", {1}, {1.0}});
  Hdf5File file = Hdf5File::create(dir_ / "r.h5");
  try {
    write_run(file, job_, record_);
    FAIL() << "an undescribed dataset was written";
  } catch (const std::logic_error& e) {
    EXPECT_NE(std::string(e.what()).find("surprise"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("dataset_schema.cpp"), std::string::npos) << e.what();
  }
  record_.fits.front().arrays.back() = {"steps_to_goal", {1, 1}, {3}, ElementType::kInt32};
  record_.fits.front().arrays.erase(record_.fits.front().arrays.begin());
  EXPECT_THROW(write_run(file, job_, record_), std::logic_error);  // rank 2, schema 1
}

// "scalar" names a dataset of no dimension; every other entry names one axis per
// dimension, so the rank check is exact for every dataset.
TEST(DatasetSchema, DimsNameTheRankExactly) {
  EXPECT_EQ(dims_rank("scalar"), 0u);
  EXPECT_EQ(dims_rank("value"), 1u);
  EXPECT_EQ(dims_rank("node,observation_dim"), 2u);
  EXPECT_THROW(dims_rank(""), std::logic_error);
  EXPECT_THROW(dims_rank("node,,sensor"), std::logic_error);
  EXPECT_THROW(dims_rank("node,scalar"), std::logic_error);
  for (const DatasetSchema& schema : dataset_schemas()) {
    EXPECT_NO_THROW(dims_rank(schema.dims)) << schema.path;
  }
}

TEST(DatasetSchema, ResultsReadmeHoldsTheSchemasTable) {
  const char* source = std::getenv("GGK_SOURCE_DIR");
  ASSERT_NE(source, nullptr) << "ctest sets GGK_SOURCE_DIR";
  const fs::path readme = fs::path(source) / "results" / "README.md";
  std::ifstream in(readme);
  std::stringstream text;
  text << in.rdbuf();
  const std::string all = text.str();
  const std::size_t begin = all.find(kBegin);
  const std::size_t end = all.find(kEnd);
  ASSERT_NE(begin, std::string::npos) << readme << " has no line " << kBegin;
  ASSERT_NE(end, std::string::npos) << readme << " has no line " << kEnd;
  const std::size_t first = begin + std::string(kBegin).size() + 1;
  EXPECT_EQ(all.substr(first, end - first), dataset_schema_markdown())
      << readme << ": the table between the two marks is not the schema's; put this there:\n"
      << dataset_schema_markdown();
}

}  // namespace
}  // namespace ggk::engine
