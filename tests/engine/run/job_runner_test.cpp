#include "engine/run/job_runner.hpp"

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include <gtest/gtest.h>

#include "engine/hdf5/hdf5_file.hpp"
#include "engine/job/job_file.hpp"
#include "engine/job/sweep.hpp"
#include "engine/store/run_store.hpp"
#include "engine/tasks/discrete_protocol.hpp"
#include "engine/tasks/task_list.hpp"
#include "sims/maze/maze.hpp"
#include "sims/maze/maze_config.hpp"
#include "support/determinism_job.hpp"
#include "support/results_compare.hpp"

namespace ggk::engine {
namespace {

namespace fs = std::filesystem;
using namespace test_support;

// "2024-09-17T08:30:00Z" (std::regex would do, but GCC 12 warns inside it
// under the sanitizers).
bool is_utc_timestamp(const std::string& text) {
  const std::string pattern = "dddd-dd-ddTdd:dd:ddZ";
  if (text.size() != pattern.size()) return false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const bool digit = text[i] >= '0' && text[i] <= '9';
    if (pattern[i] == 'd' ? !digit : text[i] != pattern[i]) return false;
  }
  return true;
}

// ---------------------------------------------------------------------------

TEST_F(JobRunnerTest, ResultsAreBitIdenticalForOneTwoAndEightThreads) {
  const JobSpec job = load_job("job.toml", determinism_job(dir_ / "unused.h5"));
  const std::vector<std::int32_t> thread_counts = {1, 2, 8};
  for (std::int32_t threads : thread_counts) {
    const fs::path output = dir_ / ("threads_" + std::to_string(threads) + ".h5");
    const RunSummary summary = run_job(job, options_for(output, threads));
    EXPECT_EQ(summary.runs_computed, 3);
    EXPECT_EQ(summary.fits, 3 * 8);
    EXPECT_EQ(summary.failed_fits, 0);
  }
  // The comparison must see real fits: converged policies, goals reached.
  {
    const Hdf5File file = Hdf5File::open_read_only(dir_ / "threads_1.h5");
    for (const TableRow& row : file.read_table("/maze/summary")) {
      EXPECT_NE(std::get<std::string>(row.at(7)), "invalid");
    }
    EXPECT_GT(
        file.read_vector<double>("/maze/run_000/fits/ggk/k_0008_sigma3_brm_lambda1e-06/weights")
            .size(),
        0u);
  }
  for (const char* other : {"threads_2.h5", "threads_8.h5"}) {
    SCOPED_TRACE(std::string("threads_1.h5 vs ") + other);
    expect_identical_results(job, dir_ / "threads_1.h5", dir_ / other);
  }
}

TEST_F(JobRunnerTest, ComputeRunIsRepeatableAndMatchesTheStore) {
  const JobSpec job = load_job("job.toml", determinism_job(dir_ / "out.h5"));
  const RunRecord first = compute_run(job, 1);
  const RunRecord again = compute_run(job, 1);
  const RunRecord other = compute_run(job, 2);
  ASSERT_EQ(first.fits.size(), 8u);
  ASSERT_EQ(first.run, 1);
  EXPECT_EQ(first.samples.actions, again.samples.actions);
  EXPECT_NE(first.samples.actions, other.samples.actions) << "runs must draw distinct samples";

  run_job(job, options_for(job.output.file));
  const Hdf5File file = Hdf5File::open_read_only(job.output.file);
  for (std::size_t i = 0; i < first.fits.size(); ++i) {
    const FitRecord& fit = first.fits[i];
    const std::string group = "/maze/run_001/fits/" + fit_group_name(job, fit.point);
    SCOPED_TRACE(group);
    EXPECT_EQ(fit.status, again.fits[i].status);
    const std::vector<double> weights(fit.lspi.weights.data(),
                                      fit.lspi.weights.data() + fit.lspi.weights.size());
    const std::vector<double> weights_again(
        again.fits[i].lspi.weights.data(),
        again.fits[i].lspi.weights.data() + again.fits[i].lspi.weights.size());
    EXPECT_TRUE(same_bits(weights, weights_again));
    EXPECT_TRUE(same_bits(weights, file.read_vector<double>(group + "/weights")));
    EXPECT_EQ(fit.lspi.policy, file.read_vector<std::int32_t>(group + "/policy"));
    EXPECT_EQ(fit.centers, file.read_vector<std::int32_t>(group + "/centers"));
    EXPECT_EQ(fit.status, file.read_string_attribute(group, "status"));
  }
}

TEST_F(JobRunnerTest, TooManyKernelsIsAnInvalidFitAndTheOthersStillRun) {
  // 27 states: 50 kernels exceed every run's sample graph.
  std::string text = determinism_job(dir_ / "out.h5");
  text.replace(text.find("kernels = [4, 8]"), 16, "kernels = [4, 50]");
  const JobSpec job = load_job("job.toml", text);
  const std::vector<SweepPoint> points = expand_sweep(job);

  const RunRecord record = compute_run(job, 0);
  ASSERT_EQ(record.fits.size(), points.size());
  std::int32_t invalid = 0;
  for (const FitRecord& fit : record.fits) {
    SCOPED_TRACE(fit_group_name(job, fit.point));
    const std::map<std::string, double> metrics(fit.metrics.begin(), fit.metrics.end());
    if (fit.point.kernels == 50) {
      ++invalid;
      EXPECT_EQ(fit.status, "invalid");
      EXPECT_NE(fit.message.find("50 kernels"), std::string::npos) << fit.message;
      EXPECT_NE(fit.message.find("nodes"), std::string::npos) << fit.message;
      EXPECT_TRUE(std::isnan(metrics.at("success_rate")));
      EXPECT_TRUE(std::isnan(metrics.at("mean_steps_to_goal")));
      EXPECT_EQ(fit.lspi.weights.size(), 0);
      EXPECT_TRUE(fit.centers.empty());
    } else {
      EXPECT_NE(fit.status, "invalid");
      EXPECT_NE(fit.status, "solver_failed") << fit.message;
      EXPECT_TRUE(std::isfinite(metrics.at("success_rate")));
      EXPECT_EQ(fit.lspi.weights.size(), 4 * 4);
    }
    EXPECT_GT(metrics.at("graph_nodes"), 4.0);
    EXPECT_LE(metrics.at("graph_nodes"), 27.0);
  }
  EXPECT_EQ(invalid, 4);

  const RunSummary summary = run_job(job, options_for(job.output.file));
  EXPECT_EQ(summary.failed_fits, 3 * 4);
  const Hdf5File file = Hdf5File::open_read_only(job.output.file);
  const std::vector<TableColumn> columns = file.read_table_columns("/maze/summary");
  std::map<std::string, std::size_t> column;
  for (std::size_t c = 0; c < columns.size(); ++c) column[columns[c].name] = c;
  for (const TableRow& row : file.read_table("/maze/summary")) {
    const bool too_many = std::get<std::int32_t>(row.at(column.at("kernels"))) == 50;
    const std::string status = std::get<std::string>(row.at(column.at("status")));
    const double success = std::get<double>(row.at(column.at("success_rate")));
    EXPECT_EQ(status == "invalid", too_many) << status;
    EXPECT_EQ(std::isnan(success), too_many);
  }
  const std::string group = "/maze/run_002/fits/ogk/k_0050_sigma3_lstdq_lambda1e-06";
  EXPECT_EQ(file.read_string_attribute(group, "status"), "invalid");
  EXPECT_NE(file.read_string_attribute(group, "message").find("50 kernels"), std::string::npos);
  EXPECT_TRUE(std::isnan(file.read_double_attribute(group, "success_rate")));
  EXPECT_TRUE(file.read_vector<double>(group + "/weights").empty());
  EXPECT_FALSE(file.exists(group + "/steps_to_goal"));
  EXPECT_GT(
      file.read_vector<double>("/maze/run_002/fits/ogk/k_0004_sigma3_lstdq_lambda1e-06/weights")
          .size(),
      0u);
}

TEST_F(JobRunnerTest, FileFollowsTheDocumentedSchema) {
  const char* source_dir = std::getenv("GGK_SOURCE_DIR");
  if (source_dir == nullptr) GTEST_SKIP() << "GGK_SOURCE_DIR is not set (run through ctest)";
  const fs::path map_file = fs::path(source_dir) / "jobs" / "maps" / "four-rooms.txt";
  const std::string text = R"(name = "schema"
task = "maze"
runs = 2
seed = 99
[sweep]
basis = ["ggk", "ogk"]
kernels = [4, 8]
sigma = [5.0]
[maze]
map_file = ")" + map_file.string() +
                           R"("
series = 20
steps_per_series = 250
[output]
file = ")" + (dir_ / "schema.h5").string() +
                           R"("
)";
  const JobSpec job = load_job("schema.toml", text);
  const RunSummary summary = run_job(job, options_for(job.output.file));
  EXPECT_EQ(summary.output, job.output.file) << "no -o: the job's [output] file";
  const sims::maze::Maze maze(task_config_as<sims::maze::MazeConfig>(job).map_text);
  const std::vector<std::int32_t>& goals = maze.goal_states();
  ASSERT_EQ(goals.size(), 4u);

  const Hdf5File file = Hdf5File::open_read_only(job.output.file);
  EXPECT_EQ(file.read_string_attribute("/", "job"), text);
  EXPECT_FALSE(file.read_string_attribute("/", "ggk_version").empty());
  EXPECT_FALSE(file.read_string_attribute("/", "git").empty());
  EXPECT_TRUE(is_utc_timestamp(file.read_string_attribute("/", "created")))
      << file.read_string_attribute("/", "created");
  EXPECT_EQ(file.read_string_attribute("/", "task"), "maze");
  EXPECT_EQ(file.read_int64_attribute("/", "runs"), 2);

  const std::vector<std::string> metrics = discrete_metric_names();
  for (std::int32_t run = 0; run < 2; ++run) {
    const std::string group = run_group("maze", run);
    SCOPED_TRACE(group);
    ASSERT_TRUE(run_is_complete(file, "maze", run));

    const std::string s = group + "/samples";
    const RowMajorArray<double> obs = file.read_matrix<double>(s + "/observations");
    const RowMajorArray<double> next = file.read_matrix<double>(s + "/next_observations");
    const auto actions = file.read_vector<std::int32_t>(s + "/actions");
    const auto rewards = file.read_vector<double>(s + "/rewards");
    const auto terminals = file.read_vector<std::uint8_t>(s + "/terminals");
    EXPECT_EQ(obs.rows, 20 * 250);
    EXPECT_EQ(obs.cols, 2);
    EXPECT_EQ(next.rows, obs.rows);
    EXPECT_EQ(next.cols, 2);
    EXPECT_EQ(static_cast<std::int64_t>(actions.size()), obs.rows);
    EXPECT_EQ(static_cast<std::int64_t>(rewards.size()), obs.rows);
    EXPECT_EQ(static_cast<std::int64_t>(terminals.size()), obs.rows);
    for (std::size_t i = 0; i < actions.size(); ++i) {
      ASSERT_GE(actions[i], 0);
      ASSERT_LT(actions[i], maze.num_actions());
      ASSERT_EQ(rewards[i], terminals[i] ? 1.0 : 0.0) << "sample " << i;
    }

    // The graph: a symmetric CSR over every state, with the states' vectors.
    const CsrArrays graph = file.read_csr(group + "/graph", "weights");
    ASSERT_EQ(graph.rows, maze.num_states());
    ASSERT_EQ(graph.cols, maze.num_states());
    ASSERT_EQ(graph.indptr.size(), static_cast<std::size_t>(graph.rows) + 1);
    EXPECT_EQ(graph.indptr.front(), 0);
    EXPECT_EQ(graph.indptr.back(), static_cast<std::int64_t>(graph.indices.size()));
    ASSERT_EQ(graph.indices.size(), graph.data.size());
    EXPECT_GT(graph.indices.size(), 0u);
    std::map<std::pair<std::int32_t, std::int32_t>, double> edges;
    for (std::int64_t i = 0; i < graph.rows; ++i) {
      ASSERT_LE(graph.indptr[static_cast<std::size_t>(i)],
                graph.indptr[static_cast<std::size_t>(i) + 1]);
      for (auto e = graph.indptr[static_cast<std::size_t>(i)];
           e < graph.indptr[static_cast<std::size_t>(i) + 1]; ++e) {
        const std::int32_t j = graph.indices[static_cast<std::size_t>(e)];
        ASSERT_GE(j, 0);
        ASSERT_LT(j, graph.cols);
        EXPECT_NE(j, i) << "self loop";
        EXPECT_EQ(graph.data[static_cast<std::size_t>(e)], 1.0) << "maze moves are unit steps";
        edges[{static_cast<std::int32_t>(i), j}] = graph.data[static_cast<std::size_t>(e)];
      }
    }
    for (const auto& [edge, weight] : edges) {
      const auto reverse = edges.find({edge.second, edge.first});
      ASSERT_NE(reverse, edges.end()) << edge.first << " -> " << edge.second << " has no reverse";
      EXPECT_EQ(reverse->second, weight);
    }
    const RowMajorArray<double> nodes = file.read_matrix<double>(group + "/graph/nodes");
    const kernels::RowMatrixXd states = maze.state_vectors();
    ASSERT_EQ(nodes.rows, maze.num_states());
    ASSERT_EQ(nodes.cols, 2);
    EXPECT_TRUE(std::equal(nodes.data.begin(), nodes.data.end(), states.data()));

    const std::vector<std::uint8_t> visited =
        file.read_vector<std::uint8_t>(group + "/graph/visited");
    ASSERT_EQ(visited.size(), static_cast<std::size_t>(maze.num_states()));
    std::vector<std::int32_t> visited_goals;
    for (std::int32_t g : goals) {
      if (visited[static_cast<std::size_t>(g)] == 1) visited_goals.push_back(g);
    }
    ASSERT_GE(visited_goals.size(), 1u) << "the samples must reach a goal";

    // One fit group per sweep point; the first centres are the goals.
    for (const char* basis : {"ggk", "ogk"}) {
      for (std::int32_t kernels : {4, 8}) {
        char name[64];
        std::snprintf(name, sizeof name, "%s/fits/%s/k_%04d_sigma5_brm_lambda1e-06", group.c_str(),
                      basis, kernels);
        const std::string fit = name;
        SCOPED_TRACE(fit);
        ASSERT_TRUE(file.exists(fit));
        EXPECT_EQ(file.read_string_attribute(fit, "basis"), basis);
        EXPECT_EQ(file.read_int64_attribute(fit, "kernels"), kernels);
        EXPECT_EQ(file.read_double_attribute(fit, "sigma"), 5.0);
        EXPECT_EQ(file.read_string_attribute(fit, "solver"), "brm");
        const auto centers = file.read_vector<std::int32_t>(fit + "/centers");
        ASSERT_EQ(centers.size(), static_cast<std::size_t>(kernels));
        // Visited goals first (the goal cell walled in by other goals is never
        // entered: episodes end on the first goal), then other visited states.
        ASSERT_GE(centers.size(), visited_goals.size());
        EXPECT_TRUE(std::equal(visited_goals.begin(), visited_goals.end(), centers.begin()))
            << "the first centres must be the visited goal states";
        for (std::size_t j = 0; j < centers.size(); ++j) {
          ASSERT_GE(centers[j], 0);
          ASSERT_LT(centers[j], maze.num_states());
          EXPECT_EQ(visited[static_cast<std::size_t>(centers[j])], 1) << "centre " << j;
          if (j >= visited_goals.size()) {
            EXPECT_FALSE(maze.is_goal(centers[j])) << "centre " << j;
          }
        }
        EXPECT_EQ(std::set<std::int32_t>(centers.begin(), centers.end()).size(), centers.size());
        EXPECT_EQ(file.read_vector<double>(fit + "/weights").size(),
                  static_cast<std::size_t>(kernels) * 4);
        EXPECT_EQ(file.read_vector<std::int32_t>(fit + "/policy").size(),
                  static_cast<std::size_t>(maze.num_states()));
        for (const std::string& metric : metrics) EXPECT_TRUE(file.has_attribute(fit, metric));
        EXPECT_EQ(file.read_vector<std::int32_t>(fit + "/steps_to_goal").size(),
                  static_cast<std::size_t>(maze.num_states()) - goals.size());
        EXPECT_EQ(file.read_vector<double>(fit + "/state_values").size(),
                  static_cast<std::size_t>(maze.num_states()));
      }
    }
    // The ggk and ogk fits of a run share its centres (paired comparison).
    EXPECT_EQ(
        file.read_vector<std::int32_t>(group + "/fits/ggk/k_0008_sigma5_brm_lambda1e-06/centers"),
        file.read_vector<std::int32_t>(group + "/fits/ogk/k_0008_sigma5_brm_lambda1e-06/centers"));
    EXPECT_EQ(file.read_table(group + "/fit_metrics").size(), 4u);
  }

  // Whole-number metrics are int64 columns (graph_protocol.hpp: MetricSpec::integer).
  EXPECT_EQ(file.read_table_columns("/maze/summary"),
            summary_columns(metrics, {"lspi_iterations", "graph_nodes", "edges"}));
  EXPECT_EQ(summary_keys(job.output.file, "maze"), every_fit_once(job));
}

}  // namespace
}  // namespace ggk::engine
