// The axes, units and descriptions of a run's datasets: every dataset the writer
// makes is described by the store's declarations or its task's, a dataset nobody
// declared is refused, and results/README.md's table is the store's and every
// registered task's declarations.

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
#include "engine/tasks/task_list.hpp"

namespace ggk::engine {
namespace {

namespace fs = std::filesystem;

constexpr const char* kBegin =
    "<!-- dataset schema: generated from the store's and the tasks' declarations -->";

// The declarations of a registered task.
std::span<const DatasetSpecs> declared_by(std::string_view task) {
  return find_task(task)->datasets;
}

// Every registered task's lists, in task order.
std::vector<DatasetSpecs> every_task_declaration() {
  std::vector<DatasetSpecs> all;
  for (const TaskDefinition& task : registered_tasks()) {
    all.insert(all.end(), task.datasets.begin(), task.datasets.end());
  }
  return all;
}
constexpr const char* kEnd = "<!-- end of dataset schema -->";

TEST(DatasetSchema, FindsRunAndFitDatasets) {
  ASSERT_NE(dataset_spec_of("samples/actions"), nullptr);
  EXPECT_EQ(dataset_spec_of("samples/actions")->dims, "sample");
  EXPECT_EQ(dataset_spec_of("graph/nodes")->dims, "node,observation_dim");
  const std::string fit = "fits/ggk/k_0016_sigma5_brm_lambda1e-06/";
  const auto maze = declared_by("maze");
  EXPECT_EQ(dataset_spec_of(fit + "history/weights", maze)->dims, "iteration,coefficient");
  EXPECT_EQ(dataset_spec_of(fit + "history/rcond")->dims, "iteration");               // the store's
  EXPECT_EQ(dataset_spec_of(fit + "history/success_rate", maze)->dims, "iteration");  // history/*
  EXPECT_EQ(dataset_spec_of(fit + "steps_to_goal", maze)->dims, "start");
  EXPECT_EQ(dataset_spec_of(fit + "trajectory_A", declared_by("arm"))->dims, "step");
  // A task's own declaration first (the Khepera's poses), then its protocol's.
  EXPECT_EQ(dataset_spec_of(fit + "evaluation/trajectory_3", declared_by("khepera"))->dims,
            "step,pose");
  EXPECT_EQ(dataset_spec_of(fit + "evaluation/trajectory_3", declared_by("pendulum"))->dims,
            "step,state_field");
  EXPECT_EQ(dataset_spec_of("som/prototypes", declared_by("khepera"))->units, "IR reading");
  EXPECT_EQ(dataset_spec_of("som/prototypes", declared_by("pendulum"))->units,
            "scaled state units");
  EXPECT_EQ(dataset_spec_of("samples/actions", declared_by("khepera"))->dims, "sample");
  // What only a task declares is unknown without its declarations, and another
  // task's arrays are not this task's.
  EXPECT_EQ(dataset_spec_of(fit + "steps_to_goal"), nullptr);
  EXPECT_EQ(dataset_spec_of("samples/collisions", declared_by("maze")), nullptr);
  EXPECT_EQ(dataset_spec_of("optimal_actions", declared_by("arm")), nullptr);
  EXPECT_NE(dataset_spec_of("optimal_actions", declared_by("chain")), nullptr);
  EXPECT_EQ(dataset_spec_of("steps_to_goal", maze), nullptr);  // a fit's, not a run's
  EXPECT_EQ(dataset_spec_of("fit:policy"), nullptr);
  EXPECT_EQ(dataset_spec_of("no_such_array", maze), nullptr);
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
    // The maze's declarations and, for robot/radius, the Khepera's own list.
    record_.dataset_specs = {declared_by("khepera").front()};
    for (const DatasetSpecs& list : declared_by("maze")) record_.dataset_specs.push_back(list);
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
    EXPECT_NE(std::string(e.what()).find("dataset_spec.hpp"), std::string::npos) << e.what();
  }
  record_.fits.front().arrays.back() = {"steps_to_goal", {1, 1}, {3}, ElementType::kInt32};
  record_.fits.front().arrays.erase(record_.fits.front().arrays.begin());
  EXPECT_THROW(write_run(file, job_, record_), std::logic_error);  // rank 2, declared 1
}

// A task's arrays need its declarations: the same record without them is refused.
TEST_F(DescribedRunTest, ATasksArrayWithoutItsDeclarationsIsRefused) {
  record_.dataset_specs.clear();
  Hdf5File file = Hdf5File::create(dir_ / "r.h5");
  try {
    write_run(file, job_, record_);
    FAIL() << "the maze's arrays were written without its declarations";
  } catch (const std::logic_error& e) {
    EXPECT_NE(std::string(e.what()).find("has no declaration"), std::string::npos) << e.what();
  }
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
  for (const DatasetSpec& spec : store_dataset_specs()) {
    EXPECT_NO_THROW(dims_rank(spec.dims)) << spec.path;
  }
  for (const DatasetSpecs& list : every_task_declaration()) {
    for (const DatasetSpec& spec : list.specs) {
      EXPECT_NO_THROW(dims_rank(spec.dims)) << list.declared_by << ": " << spec.path;
    }
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
  const std::string table = dataset_schema_markdown(every_task_declaration());
  EXPECT_EQ(all.substr(first, end - first), table)
      << readme << ": the table between the two marks is not the declarations'; put this there:\n"
      << table;
}

}  // namespace
}  // namespace ggk::engine
